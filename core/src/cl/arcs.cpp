// The CL reader's arcs: CIRCLE, checked against the GOTO that ends it, and given out whole as
// one arc event (ClReader::Impl, cl/reader_impl.hpp; the geometry is in cl/arc_chords.hpp). The
// expander chords it for hosts that read plain moves; a post session writes a CIRC or chords.
#include <string>
#include <string_view>

#include "cl/arc_chords.hpp"
#include "cl/reader_impl.hpp"

namespace redpost {

void ClReader::Impl::on_circle() {
  split_fields();
  const std::size_t n = fields.size();
  if (n == 13 && is(fields[11], "TIMES"))
    fail_at(fields[11].offset,
            "CIRCLE/...,TIMES,n (a helix of several turns) is not supported; output the helix "
            "as GOTO points");
  if (n != 6 && n != 7 && n != 11) {
    fail_at(n > 6 ? fields[n - 1].offset : word_offset,
            "CIRCLE takes 6 values (xc,yc,zc,i,j,k), 7 (...,r) or 11 (...,r,t,f,d,e), got " +
                std::to_string(n));
  }
  arc_centre = point(0);
  const Vector3d a = unit_vector(3, "the circle axis");
  // NX writes the axis "assuming a clockwise direction" (NX CLSF manual, CIRCLE); APT and
  // SolidWorks CAM by the right-hand rule. Keep the right-hand one.
  arc_axis = nx ? Vector3d(-a) : a;
  arc_has_radius = n >= 7;
  if (arc_has_radius) {
    arc_radius_mm = length(fields[6]);
    if (!(arc_radius_mm > 0.0))
      fail_at(fields[6].offset,
              "the circle radius must be > 0, got " + std::string(fields[6].text));
    for (std::size_t i = 7; i < n; ++i)
      number(fields[i]);  // tolerances and tool size: checked, not needed
  }
  if (!pos_known)
    fail_word("CIRCLE needs a start point, but no position is known yet");
  current_axis();
  arc_pending = true;
  arc_line = record_line;
}

// Between CIRCLE and its GOTO only non-motion records may come (FEDRAT, PAINT, comments...).
void ClReader::Impl::check_arc_not_interrupted() const {
  static constexpr std::string_view kBreakers[] = {
      "GODLTA", "FROM",   "CIRCLE", "NURBS", "CYCLE", "END-OF-PATH", "TOOL PATH", "END",
      "FINI",   "LOADTL", "LOAD",   "UNITS", "UNIT",  "MULTAX",      "TLAXIS"};
  for (std::string_view b : kBreakers) {
    if (word == b) {
      fail_word("CIRCLE at line " + std::to_string(arc_line) +
                " must be followed by the GOTO that ends the arc, not by " + word);
    }
  }
}

void ClReader::Impl::start_arc(const Vector3d& end) {
  arc_pending = false;
  detail::ArcWording wording;
  wording.circle = "the circle of the CIRCLE at line " + std::to_string(arc_line);
  const detail::ArcBuild built =
      detail::make_arc_chords(pos, arc_centre, arc_axis, arc_has_radius ? arc_radius_mm : 0.0, end,
                              opt.point_match_tolerance_mm, opt.chordal_tolerance_mm, wording);
  switch (built.problem) {
    case detail::ArcProblem::none:
      break;
    case detail::ArcProblem::end_off_circle:
      // The GOTO is the culprit: point at its values.
      fail_at(fields[0].offset, built.message);
    case detail::ArcProblem::start_on_axis:
    case detail::ArcProblem::start_off_radius:
    case detail::ArcProblem::too_many_chords:
      fail_line(arc_line, built.message);
  }
  // One event for the whole arc: the session writes it as a CIRC where it can (its template set
  // has one and the arc passes the replay), else as chords; the expander chords it for hosts
  // that read plain moves.
  ClEvent& e = push(ClEventKind::arc, record_line);
  e.p_mm = end;
  e.tool_axis = axis;
  e.arc_centre_mm = arc_centre;
  e.arc_axis = arc_axis;
  e.value = arc_has_radius ? arc_radius_mm : 0.0;
  e.rapid = take_rapid();
  e.origin = MoveOrigin::arc;
  pos = end;
  pos_known = true;
}

}  // namespace redpost
