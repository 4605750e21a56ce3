// The CL reader's event queue and its straight motion records: GOTO, FROM, GODLTA, RAPID and
// TLAXIS (ClReader::Impl, cl/reader_impl.hpp).
#include <string>
#include <string_view>

#include "cl/reader_impl.hpp"

namespace redpost {

using Eigen::Vector3d;

// ===========================================================================================
// Events

ClEvent& ClReader::Impl::push(ClEventKind kind, int line_no) {
  queue.emplace_back();
  ClEvent& e = queue.back();
  e.kind = kind;
  e.line = line_no;
  return e;
}

ClEvent& ClReader::Impl::push_move(const Vector3d& p, const Vector3d& tool_axis, MoveOrigin origin,
                                   bool rapid, int line_no) {
  // Most CAM systems write no UNITS record (NX CLSF never does) and mean mm; a file in inches
  // without one would come out 25.4 times too small. Say so once, where it matters.
  if (!units_given)
    warn_once("UNITS", line_no,
              "no UNITS record before the first motion: coordinates are read as mm (add "
              "UNITS/INCHES at the top of the file if the CAM system wrote inches)");
  ClEvent& e = push(ClEventKind::move, line_no);
  e.p_mm = p;
  e.tool_axis = tool_axis;
  e.origin = origin;
  e.rapid = rapid;
  return e;
}

void ClReader::Impl::push_feed(double mm_per_min, int line_no) {
  push(ClEventKind::feed, line_no).value = mm_per_min;
}

void ClReader::Impl::push_text(ClEventKind kind, std::string_view text) {
  push(kind, record_line).text.assign(text.data(), text.size());
}

bool ClReader::Impl::take_rapid() {
  const bool r = rapid_next;
  rapid_next = false;
  return r;
}

// The tool axis for a motion that gives none.
const Vector3d& ClReader::Impl::current_axis() const {
  if (!axis_known && multax) {
    fail_word(word +
              " before any tool axis is known: with MULTAX/ON give TLAXIS/i,j,k or a GOTO "
              "with i,j,k first");
  }
  return axis;  // +Z until a TLAXIS or a GOTO with i,j,k says otherwise
}

// ===========================================================================================
// Motion

// A GOTO (a hole while a drilling cycle is on: the expander decides) or a FROM.
void ClReader::Impl::on_goto(MoveOrigin origin) {
  split_fields();
  expect_count(3, 6, "3 values (x,y,z) or 6 (x,y,z,i,j,k)");
  if (fields.size() != 3 && fields.size() != 6)
    fail_at(fields[3].offset, word + " takes 3 values (x,y,z) or 6 (x,y,z,i,j,k), got " +
                                  std::to_string(fields.size()) + " values");
  const Vector3d p = point(0);
  if (fields.size() == 6) {
    axis = unit_vector(3, "the tool axis");
    axis_known = true;
  } else {
    current_axis();
  }
  if (arc_pending && origin == MoveOrigin::goto_point) {
    start_arc(p);
    return;
  }
  push_move(p, axis, origin, take_rapid(), record_line);
  // A hole leaves the tool at its retract height above the point.
  pos = cycle_on && origin == MoveOrigin::goto_point ? Vector3d(p + cycle_retract_mm * axis) : p;
  pos_known = true;
}

// GODLTA/d (along the tool axis) or GODLTA/dx,dy,dz: the expander adds it to where the tool is.
void ClReader::Impl::on_godlta() {
  split_fields();
  expect_count(1, 3, "1 value (a distance along the tool axis) or 3 (dx,dy,dz)");
  if (fields.size() == 2)
    fail_word("GODLTA takes 1 value (a distance along the tool axis) or 3 (dx,dy,dz), got 2");
  if (!pos_known)
    fail_word("GODLTA needs a known position, but no GOTO or FROM came before it");
  const bool along_axis = fields.size() == 1;
  const double d = along_axis ? length(fields[0]) : 0.0;
  const Vector3d delta = along_axis ? Vector3d(d * current_axis()) : point(0);
  if (!along_axis)
    current_axis();
  ClEvent& e = push_move(along_axis ? Vector3d::Zero() : delta, axis, MoveOrigin::delta,
                         take_rapid(), record_line);
  e.flag = along_axis;
  e.value = d;
  pos += delta;
}

void ClReader::Impl::on_rapid() {
  split_fields();
  if (!fields.empty())
    fail_at(fields[0].offset, "RAPID takes no values");
  rapid_next = true;
  push(ClEventKind::rapid, record_line);
}

void ClReader::Impl::on_tlaxis() {
  split_fields();
  expect_count(3, 3, "3 values (i,j,k); other forms such as TLAXIS/NORMPS are not supported");
  axis = unit_vector(0, "the tool axis");
  axis_known = true;
}

}  // namespace redpost
