// The CL reader's NURBS: the NURBS/ block with its KNOT/ and CNTRL/ records, read and checked
// value by value, and given out as one NURBS event (ClReader::Impl, cl/reader_impl.hpp). The
// expander completes its knot vector from the current point and splits it into chords
// (cl/expander_curves.cpp), the same way for NX's MOM_nurbs_move.
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "cl/reader_impl.hpp"

namespace redpost {

namespace {

std::string fmt_mm(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

}  // namespace

void ClReader::Impl::on_nurbs() {
  split_fields();
  if (!fields.empty())
    fail_at(fields[0].offset, "NURBS/ takes no values (its data follow in KNOT/ and CNTRL/)");
  if (!pos_known)
    fail_word("NURBS needs a start point, but no position is known yet");
  current_axis();
  collecting_nurbs = true;
  nurbs_line = record_line;
  nurbs_rapid = take_rapid();
  nurbs_knots.clear();
  nurbs_points.clear();
}

void ClReader::Impl::on_knot() {
  split_fields();
  if (fields.empty())
    fail_word("KNOT/ needs at least one value");
  if (!nurbs_points.empty())
    fail_word("KNOT/ after CNTRL/: all knots must come before the control points");
  for (const Field& f : fields) {
    const double k = number(f);
    if (!nurbs_knots.empty() && k < nurbs_knots.back()) {
      fail_at(f.offset, "knot " + std::string(f.text) + " is smaller than the one before it (" +
                            fmt_mm(nurbs_knots.back()) + "): knots must not decrease");
    }
    nurbs_knots.push_back(k);
  }
}

void ClReader::Impl::on_cntrl() {
  split_fields();
  expect_count(3, 4, "3 values (x,y,z) or 4 (x,y,z,weight)");
  const Vector3d p = point(0);
  double w = 1.0;
  if (fields.size() == 4) {
    w = number(fields[3]);
    if (!(w > 0.0))
      fail_at(fields[3].offset, "a NURBS weight must be > 0, got " + std::string(fields[3].text));
  }
  nurbs_points.push_back({p.x(), p.y(), p.z(), w});
}

// The block is complete (the next record is not a KNOT/ or CNTRL/): one event with the curve as
// written, in the forms of docs/cl-format.md ("NURBS"), checked by the expander.
void ClReader::Impl::finish_nurbs() {
  collecting_nurbs = false;
  ClEvent& e = push(ClEventKind::nurbs, nurbs_line);
  e.tool_axis = axis;
  e.rapid = nurbs_rapid;
  e.origin = MoveOrigin::nurbs;
  e.nurbs_knots = nurbs_knots;
  e.nurbs_points = nurbs_points;
  if (!nurbs_points.empty()) {
    const ClNurbsPoint& last = nurbs_points.back();
    pos = Vector3d(last.x, last.y, last.z);
  }
}

}  // namespace redpost
