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

void ClReader::Impl::push_move(const Vector3d& p, const Vector3d& tool_axis, MoveOrigin origin,
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

void ClReader::Impl::on_goto(MoveOrigin origin) {
  check_cycle_not_interrupted();
  split_fields();
  expect_count(3, 6, "3 values (x,y,z) or 6 (x,y,z,i,j,k)");
  if (fields.size() != 3 && fields.size() != 6)
    fail_at(fields[3].offset, word + " takes 3 values (x,y,z) or 6 (x,y,z,i,j,k), got " +
                                  std::to_string(fields.size()) + " values");
  if (cycle.active && origin != MoveOrigin::goto_point)
    fail_word(word + " while a CYCLE is active: only GOTO (a hole) is allowed until CYCLE/OFF");
  const Vector3d p = in_frame_point(point(0));
  const Vector3d before_axis = axis;
  if (fields.size() == 6) {
    axis = in_frame_vector(unit_vector(3, "the tool axis"));
    axis_known = true;
  } else {
    current_axis();
  }
  if (arc_pending && origin == MoveOrigin::goto_point) {
    start_arc(p, before_axis);
    return;
  }
  if (cycle.active) {
    start_hole(p);
    return;
  }
  pos = p;
  pos_known = true;
  push_move(p, axis, origin, take_rapid(), record_line);
}

void ClReader::Impl::on_godlta() {
  check_cycle_not_interrupted();
  split_fields();
  expect_count(1, 3, "1 value (a distance along the tool axis) or 3 (dx,dy,dz)");
  if (fields.size() == 2)
    fail_word("GODLTA takes 1 value (a distance along the tool axis) or 3 (dx,dy,dz), got 2");
  if (cycle.active)
    fail_word("GODLTA while a CYCLE is active: only GOTO (a hole) is allowed until CYCLE/OFF");
  if (!pos_known)
    fail_word("GODLTA needs a known position, but no GOTO or FROM came before it");
  const Vector3d delta =
      fields.size() == 1 ? Vector3d(length(fields[0]) * current_axis()) : in_frame_vector(point(0));
  if (fields.size() == 3)
    current_axis();
  pos += delta;
  push_move(pos, axis, MoveOrigin::goto_point, take_rapid(), record_line);
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
  axis = in_frame_vector(unit_vector(0, "the tool axis"));
  axis_known = true;
}

}  // namespace redpost
