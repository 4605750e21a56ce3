// The front door of the CL event model (redpost/cl/expander.hpp): the dispatch of toolpath
// events, straight moves, arcs, NX's MSYS, operator text and cutter compensation. Drilling cycles
// and NURBS are in expander_curves.cpp.
#include "redpost/cl/expander.hpp"

#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "cl/expander_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

using Eigen::Vector3d;

std::string chordal_tolerance_problem(double tolerance_mm) {
  if (std::isfinite(tolerance_mm) && tolerance_mm >= kMinChordalToleranceMm)
    return {};
  return fmt::format(
      "the chordal tolerance (--chordal-tol) must be a number of mm of at least "
      "{} (0.1 um), got {:.6g}",
      kMinChordalToleranceMm, tolerance_mm);
}

ClExpander::Impl::Impl(std::string source_name, const ClExpanderOptions& options, Warn warn)
    : source(std::move(source_name)), opt(options), warn_fn(std::move(warn)) {
  if (const std::string why = chordal_tolerance_problem(opt.chordal_tolerance_mm); !why.empty())
    throw Error(ErrorCode::bad_input, why);
  if (!(opt.point_match_tolerance_mm > 0.0) || !std::isfinite(opt.point_match_tolerance_mm))
    throw Error(ErrorCode::bad_input, "point match tolerance must be a positive number of mm");
  out.reserve(kBatch + 8);
}

void ClExpander::Impl::fail(int line, const std::string& message) const {
  throw Error(ErrorCode::bad_input, message, SourceLocation{source, line, 0});
}

// A warning; with a key, only the first of that key.
void ClExpander::Impl::warn(const std::string& key, int line, const std::string& message) {
  if (!key.empty() && !warned.insert(key).second)
    return;
  if (warn_fn)
    warn_fn(format_error(SourceLocation{source, line, 0}, message));
}

ClEvent& ClExpander::Impl::emit(const ClEvent& e) {
  out.push_back(e);
  return out.back();
}

ClEvent& ClExpander::Impl::emit_kind(ClEventKind kind, int line) {
  out.emplace_back();
  ClEvent& e = out.back();
  e.kind = kind;
  e.line = line;
  return e;
}

// A point or a direction of the input, in the frame the events go out in.
Vector3d ClExpander::Impl::in_frame_point(const Vector3d& p) const {
  return frame_applied ? Vector3d(frame_origin + frame_R * p) : p;
}
Vector3d ClExpander::Impl::in_frame_vector(const Vector3d& v) const {
  return frame_applied ? Vector3d(frame_R * v) : v;
}

// The CL word an event stands for, in messages that tell the CAM user what to fix.
const char* ClExpander::Impl::word_of(const ClEvent& e) {
  switch (e.kind) {
    case ClEventKind::arc:
      return "CIRCLE";
    case ClEventKind::nurbs:
      return "NURBS";
    default:
      break;
  }
  switch (e.origin) {
    case MoveOrigin::from_point:
      return "FROM";
    case MoveOrigin::delta:
      return "GODLTA";
    default:
      return "GOTO";
  }
}

// A straight move: a hole while a cycle is on (a GOTO), refused for a FROM or a GODLTA there;
// else in the output frame. A GODLTA (origin delta) moves by p_mm (flag 0) or by `value` along
// its tool axis (flag 1) from the current position.
void ClExpander::Impl::on_move(const ClEvent& e) {
  check_cycle_not_interrupted(e);
  const Vector3d a = in_frame_vector(e.tool_axis);
  if (cycle.active) {
    if (e.origin != MoveOrigin::goto_point) {
      fail(e.line, std::string(word_of(e)) +
                       " while a CYCLE is active: only GOTO (a hole) is allowed until CYCLE/OFF");
    }
    on_hole(e, in_frame_point(e.p_mm), a);
    return;
  }
  Vector3d p;
  if (e.origin == MoveOrigin::delta) {
    if (!pos_known)
      fail(e.line, "GODLTA needs a known position, but no GOTO or FROM came before it");
    p = pos + (e.flag ? Vector3d(e.value * a) : in_frame_vector(e.p_mm));
  } else {
    p = in_frame_point(e.p_mm);
  }
  ClEvent& m = emit(e);
  m.p_mm = p;
  m.tool_axis = a;
  if (e.origin == MoveOrigin::delta) {
    m.origin = MoveOrigin::goto_point;
    m.flag = false;
    m.value = 0.0;
  }
  pos = p;
  pos_known = true;
  axis = a;
}

// An arc from the current point: whole (the session writes a CIRC or its chords), or as its
// chords for a host that reads plain moves. Its checks name the circle's own line (`value` 0:
// the radius from the start).
void ClExpander::Impl::on_arc(const ClEvent& e) {
  check_cycle_not_interrupted(e);
  if (cycle.active)
    fail(e.line, "CIRCLE while a CYCLE is active: give CYCLE/OFF first");
  const Vector3d end = in_frame_point(e.p_mm);
  const Vector3d centre = in_frame_point(e.arc_centre_mm);
  const Vector3d arc_axis = in_frame_vector(e.arc_axis);
  const Vector3d end_axis = in_frame_vector(e.tool_axis);
  if (!opt.chord_arcs) {
    ClEvent& m = emit(e);
    m.p_mm = end;
    m.arc_centre_mm = centre;
    m.arc_axis = arc_axis;
    m.tool_axis = end_axis;
  } else {
    if (!pos_known)
      fail(e.line, "CIRCLE needs a start point, but no position is known yet");
    detail::ArcWording wording;
    wording.circle = "the circle of the CIRCLE before line " + std::to_string(e.line);
    detail::ArcBuild built =
        detail::make_arc_chords(pos, centre, arc_axis, e.value, end, opt.point_match_tolerance_mm,
                                opt.chordal_tolerance_mm, wording);
    if (built.problem != detail::ArcProblem::none)
      fail(e.line, built.message);
    arc = built.arc;
    arc_done = 0;
    gen_axis = axis;
    arc_end_axis = end_axis;
    gen_rapid = e.rapid;
    gen_line = e.line;
    generator = Generator::arc;
  }
  pos = end;
  pos_known = true;
  axis = end_axis;
}

void ClExpander::Impl::run_arc() {
  while (out.size() < kBatch && arc_done < arc.chords) {
    ++arc_done;
    const bool last = arc_done == arc.chords;
    ClEvent& m = emit_kind(ClEventKind::move, gen_line);
    m.p_mm = arc.point(arc_done);
    m.tool_axis = last ? arc_end_axis : gen_axis;
    m.origin = MoveOrigin::arc;
    m.rapid = gen_rapid;
  }
  if (arc_done >= arc.chords)
    generator = Generator::none;
}

// NX's machine coordinate system (MCS): origin and X, Y axes in NX's absolute frame. NX gives
// every point, tool axis and circle of the path after it in the MCS ("x,y,z is the center ...
// in MCS", NX CLSF manual, CIRCLE); docs/cl-format.md "MSYS" gives the evidence. Under
// MsysMode::ignore the MCS is the workpiece frame that --placement puts in the cell; the MSYS is
// checked, and a later, different one refused (its operations would be in another frame).
// Under apply the data are turned into the absolute frame, each operation by its own MSYS.
void ClExpander::Impl::on_msys(const ClEvent& e) {
  const Vector3d& origin = e.p_mm;
  const Vector3d& x = e.msys_x;
  const Vector3d& y = e.msys_y;
  if (!origin.allFinite() || !x.allFinite() || !y.allFinite())
    fail(e.line, "MSYS: a value that is not a finite number");
  if (std::fabs(x.norm() - 1.0) > 1e-3 || std::fabs(y.norm() - 1.0) > 1e-3 ||
      std::fabs(x.dot(y)) > 1e-3) {
    fail(e.line, "MSYS: the X and Y axes must be orthogonal unit vectors");
  }
  Eigen::Matrix3d R;
  R.col(0) = x.normalized();
  R.col(2) = x.cross(y).normalized();
  R.col(1) = R.col(2).cross(R.col(0));
  const bool apply = opt.msys == MsysMode::apply;
  if (!apply && msys_line != 0 &&
      ((origin - msys_origin).norm() > opt.point_match_tolerance_mm ||
       (R - msys_R).cwiseAbs().maxCoeff() > 1e-6)) {
    fail(e.line,
         "this MSYS differs from the one at line " + std::to_string(msys_line) +
             ": the operations after it are in another machine coordinate system, and with "
             "--msys ignore they would all be placed as if in one. Convert with --msys apply "
             "(every operation turned into NX's absolute frame), or post each set-up on its own");
  }
  if (msys_line == 0 || apply) {
    msys_line = e.line;
    msys_R = R;
    msys_origin = origin;
  }
  if (apply) {
    frame_applied = true;
    frame_R = R;
    frame_origin = origin;
  }
  ClEvent& m = emit_kind(ClEventKind::machine_frame, e.line);
  m.p_mm = origin;
  m.tool_axis = R.col(2);
  m.flag = apply;
}

// INSERT, PPRINT and NX's operator texts carry tool holders, stock sizes, notes. Written into a
// KRL program as they stand they are a syntax error (or, worse, a statement), so they become
// comments, with a warning that names the line. Only INSERT's explicit form "KRL: statement"
// passes code through; the session checks that statement before it is written.
void ClExpander::Impl::on_text(const ClEvent& e) {
  constexpr std::string_view kPass = "KRL:";
  const std::string& text = e.text;
  const auto upper = [](char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; };
  bool pass = e.text_kind == TextKind::insert && text.size() >= kPass.size();
  for (std::size_t i = 0; pass && i < kPass.size(); ++i)
    pass = upper(text[i]) == kPass[i];
  if (pass) {
    std::size_t b = kPass.size(), n = text.size();
    while (b < n && (text[b] == ' ' || text[b] == '\t'))
      ++b;
    while (n > b && (text[n - 1] == ' ' || text[n - 1] == '\t'))
      --n;
    if (b == n)
      fail(e.line, "INSERT/KRL: needs a KRL statement after it (docs/cl-format.md, \"INSERT\")");
    ClEvent& m = emit_kind(ClEventKind::literal, e.line);
    m.text = text.substr(b, n - b);
    return;
  }
  emit_kind(ClEventKind::comment, e.line).text = text;
  if (e.text_kind == TextKind::message)
    return;
  // One warning per text, each with its line, up to a cap: a file of thousands of PPRINTs must
  // not bury the other warnings.
  constexpr int kMaxTextWarnings = 20;
  const bool insert = e.text_kind == TextKind::insert;
  if (text_warnings < kMaxTextWarnings) {
    ++text_warnings;
    warn("", e.line,
         insert ? "INSERT/ text written as a comment, not as KRL code: '" + text.substr(0, 60) +
                      (text.size() > 60 ? "...'" : "'") +
                      " (to pass a KRL statement through, write INSERT/KRL: statement)"
                : std::string("PPRINT/ text written as a comment"));
  } else {
    warn("many operator texts", e.line,
         std::string("more INSERT/PPRINT text (first not listed: this ") +
             (insert ? "INSERT" : "PPRINT") + "): all written as comments; only the first " +
             std::to_string(kMaxTextWarnings) + " are listed");
  }
}

void ClExpander::Impl::on_cutcom(const ClEvent& e) {
  if (e.flag) {
    warn("CUTCOM", e.line,
         "CUTCOM/" + e.text +
             " ignored: KRL has no cutter radius compensation; redpost takes the CL "
             "points as the tool centre (NX: 'centerline data')");
  }
}

// ===========================================================================================
// ClExpander

ClExpander::ClExpander(std::string source_name, const ClExpanderOptions& options, Warn warn)
    : impl_(std::make_unique<Impl>(std::move(source_name), options, std::move(warn))) {}

ClExpander::~ClExpander() = default;

void ClExpander::push(const ClEvent& e) {
  Impl& m = *impl_;
  m.out.clear();
  m.head = 0;
  m.generator = Impl::Generator::none;
  switch (e.kind) {
    case ClEventKind::move:
      m.on_move(e);
      break;
    case ClEventKind::arc:
      m.on_arc(e);
      break;
    case ClEventKind::hole: {
      m.check_cycle_not_interrupted(e);
      if (!m.cycle.active) {
        m.fail(e.line,
               "a hole of a drilling cycle, but no cycle is on (define one first: CYCLE/DRILL, "
               "NX's MOM_drill)");
      }
      m.on_hole(e, m.in_frame_point(e.p_mm), m.in_frame_vector(e.tool_axis));
      break;
    }
    case ClEventKind::cycle:
      m.on_cycle(e);
      break;
    case ClEventKind::cycle_on:
      if (!m.cycle.defined)
        m.fail(e.line, "CYCLE/ON without a cycle defined before it");
      m.cycle.active = true;
      m.cycle.interrupted = false;
      break;
    case ClEventKind::cycle_off:
      m.cycle.active = false;
      m.cycle.interrupted = false;
      break;
    case ClEventKind::nurbs:
      m.on_nurbs(e);
      break;
    case ClEventKind::msys:
      m.on_msys(e);
      break;
    case ClEventKind::operator_text:
      m.on_text(e);
      break;
    case ClEventKind::cutcom:
      m.on_cutcom(e);
      break;
    case ClEventKind::feed:
      m.feed_known = true;
      m.feed_mm_per_min = e.value;
      m.emit(e);
      break;
    case ClEventKind::tool_change:
    case ClEventKind::operation_start:
      m.interrupt_cycle(e.line);
      m.emit(e);
      break;
    default:
      m.emit(e);
      break;
  }
}

bool ClExpander::next(ClEvent& out) {
  Impl& m = *impl_;
  while (m.head == m.out.size()) {
    if (m.generator == Impl::Generator::none)
      return false;
    m.out.clear();
    m.head = 0;
    switch (m.generator) {
      case Impl::Generator::arc:
        m.run_arc();
        break;
      case Impl::Generator::nurbs:
        m.run_nurbs();
        break;
      case Impl::Generator::hole:
        m.run_hole();
        break;
      case Impl::Generator::none:
        break;
    }
  }
  out = std::move(m.out[m.head++]);
  return true;
}

bool ClExpander::cycle_active() const {
  return impl_->cycle.active;
}

}  // namespace redpost
