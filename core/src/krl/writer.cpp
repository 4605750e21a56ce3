// Writing a KRL program through a template set (redpost/krl/writer.hpp): the checks of the
// program's settings, and the statements and motions in the order the caller gives them.
//
// The template set is checked and compiled in writer_templates.cpp, placeholders are filled in
// writer_render.cpp, and the files (parts, main program, renames) are handled in
// writer_files.cpp.
#include "redpost/krl/writer.hpp"
#include "redpost/krl/motion_rate.hpp"
#include "redpost/krl/spline_model.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "krl/writer_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/temporaries.hpp"
#include "redpost/krl/check.hpp"

namespace redpost {

namespace {

namespace fs = std::filesystem;
using krl::one_line;
using krl::Stmt;

constexpr long kMinFileBytes = 16 * 1024;

// The program settings the writer relies on: a KRL name (short enough for its parts' names),
// counts >= 0, a distance and one-line $BASE and $TOOL.
void check_program_info(const KrlProgramInfo& info) {
  if (const std::string why = krl::identifier_problem(info.name); !why.empty()) {
    throw Error(ErrorCode::bad_input, "program name '" + info.name + "' " + why);
  }
  if (info.motions_per_file > 0 &&
      info.name.size() + krl::kPartSuffixLength > krl::kMaxIdentifierLength) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("program name '{}' has {} characters: too long to split, because "
                    "its parts are named {}{}001 and a KRL name has at most {}; use at "
                    "most {} characters",
                    info.name, info.name.size(), info.name, krl::kPartInfix,
                    krl::kMaxIdentifierLength, krl::kMaxIdentifierLength - krl::kPartSuffixLength));
  }
  if (info.motions_per_file < 0 || info.cl_line_every < 0) {
    throw Error(ErrorCode::bad_input, "motions_per_file and cl_line_every must be >= 0");
  }
  if (info.max_file_bytes != 0 && info.max_file_bytes < kMinFileBytes) {
    throw Error(ErrorCode::bad_input,
                fmt::format("a program file of at most {} bytes cannot hold a program; the byte "
                            "limit must be at least {} (16 KiB)",
                            info.max_file_bytes, kMinFileBytes));
  }
  if (!std::isfinite(info.spline_tolerance_mm) || info.spline_tolerance_mm < 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("the spline tolerance must be a finite number of mm >= 0, got {}",
                            info.spline_tolerance_mm));
  }
  if (info.machine_def < 1 || info.ex_axes < 0) {
    throw Error(ErrorCode::bad_input, "MACHINE_DEF index must be >= 1 and ex_axes >= 0");
  }
  if (!std::isfinite(info.apo_mm) || info.apo_mm < 0.0) {
    throw Error(ErrorCode::bad_input, "$APO.CDIS must be a finite distance >= 0 mm");
  }
  if (info.apo_mm > kKrlMaxApoCdisMm) {
    throw Error(ErrorCode::bad_input,
                fmt::format("$APO.CDIS {:g} mm is beyond {:g} mm: the approximation distance is "
                            "a few millimetres (--apo, default 0.5)",
                            info.apo_mm, kKrlMaxApoCdisMm));
  }
  for (const std::string* s : {&info.base, &info.tool}) {
    if (s->empty() || std::any_of(s->begin(), s->end(), [](char ch) {
          return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
        })) {
      throw Error(ErrorCode::bad_input, "$BASE and $TOOL need a one-line, non-empty value");
    }
    // Written into every program: it must be a value `redpost check` accepts (an identifier
    // of at most 24 characters, BASE_DATA[1], an aggregate, a function call).
    const char* what = s == &info.base ? "$BASE" : "$TOOL";
    const KrlFinding f = check_krl_statements(fmt::format("{} = {}", what, *s));
    if (f.line > 0) {
      const std::string shown = s->size() > 40 ? s->substr(0, 40) + "..." : *s;
      throw Error(
          ErrorCode::bad_input,
          fmt::format("{} = {}: not a value a controller takes ({}); give a KRL "
                      "name such as {}",
                      what, shown, f.message, s == &info.base ? "BASE_DATA[1]" : "TOOL_DATA[1]"));
    }
  }
}

// The {date} of the skeletons: now, in UTC.
std::string utc_date_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
}

// A set must be able to write what the cell needs: a coupled base only through {frames} and
// base_coupled (a static $BASE would put every cut turned by the table), $TOOL through
// tool_select wherever {frames} stands.
void check_frames(const KrlTemplateSet& t, const krl::CompiledTemplates& tpl,
                  const KrlProgramInfo& info, bool has_frames) {
  const auto refuse = [&](const std::string& why) {
    throw Error(ErrorCode::bad_input, "template set '" + t.name + "': " + why,
                SourceLocation{t.source_file, 0, 0});
  };
  if (info.base_coupled && (!has_frames || !tpl.has(Stmt::base_coupled))) {
    refuse(
        "the cell's table is a mathematically coupled kinematic, so $BASE must turn with it, "
        "but the set has no {frames} line in its src file with a base_coupled statement "
        "(docs/krl-templates.md, \"Base and tool\")");
  }
  if (has_frames && !info.base_coupled && !tpl.has(Stmt::base_static))
    refuse("the src file has a {frames} line but the set has no base_static statement");
  if (has_frames && !tpl.has(Stmt::tool_select))
    refuse("the src file has a {frames} line but the set has no tool_select statement");
}

void check_output_dir(const std::string& output_dir) {
  std::error_code ec;
  if (!fs::is_directory(output_dir, ec)) {
    throw Error(ErrorCode::io, "the output directory does not exist (or is not a directory)",
                SourceLocation{output_dir, 0, 0});
  }
  if (::access(output_dir.c_str(), W_OK | X_OK) != 0) {
    throw Error(ErrorCode::io, "the output directory is not writable: " + krl::errno_text(),
                SourceLocation{output_dir, 0, 0});
  }
}

}  // namespace

// --- statements ------------------------------------------------------------------------------
void KrlWriter::Impl::end_spline() {
  if (have_pending)
    write_pending(Eigen::Vector3d::Zero());
  if (in_spline) {
    put(Stmt::spline_end, Values{});
    in_spline = false;
  }
}

void KrlWriter::Impl::write_pending(const Eigen::Vector3d& end_tangent) {
  have_pending = false;
  const bool curved = !pending.start_tangent.isZero() || !end_tangent.isZero();
  if (!curved && segment_vel && info.interpolation_cycle_s > 0.0) {
    // The controller's clock: an SLIN alone between two corners is a motion of its own.
    const double vel = std::isnan(pending.vel) ? vel_in_force : pending.vel;
    const double rate =
        krl_cycle_velocity((pending.motion.T_base_tcp.translation() - pending.start).norm(), vel,
                           info.interpolation_cycle_s, t.position_decimals, t.velocity_decimals);
    if (rate < vel) {
      pending.vel = rate;
      if (rate_segments.size() >= 4096)  // nobody asks: keep the memory bounded
        rate_segments.pop_front();
      rate_segments.emplace_back(pending.index, rate);
    }
  }
  Values v = pose_values(pending.motion);
  if (std::isnan(pending.vel)) {
    put(curved ? Stmt::spline_spl : Stmt::spline_lin, v);
  } else {
    v.number_value = pending.vel;
    put(curved ? Stmt::spline_spl_vel : Stmt::spline_lin_vel, v);
  }
  for (const std::string& text : pending.after)
    put(src_out, out_index, text);
  pending.after.clear();
}

void KrlWriter::Impl::put_in_block(std::string text) {
  if (have_pending)
    pending.after.push_back(std::move(text));
  else
    put(src_out, out_index, text);
}

void KrlWriter::Impl::begin_spline() {
  flush_velocity();
  put(Stmt::spline_begin, Values{});
  in_spline = true;
  spline_points = 0;
}

// A feed move in a set with SPL: the segment held before it learns how its end is passed (a
// smooth knot, or a corner where the block ends and the next begins), and this one is held.
void KrlWriter::Impl::spline_feed_move(const KrlMotion& m) {
  if (in_spline && spline_points == t.max_spline_points)
    end_spline();
  if (!in_spline)
    begin_spline();
  const Eigen::Vector3d p = m.T_base_tcp.translation();
  Eigen::Vector3d tangent = Eigen::Vector3d::Zero();
  joined_smoothly = false;
  if (have_pending) {
    const Eigen::Vector3d a = pending.start, b = pending.motion.T_base_tcp.translation();
    if (smooth_knot(a, b, p, info.spline_tolerance_mm)) {
      tangent = bessel_tangent(a, b, p);
      joined_smoothly = !tangent.isZero();
    }
    if (joined_smoothly) {
      write_pending(tangent);
    } else {
      // A corner: the block ends there and the next one is blended into it ($APO.CDIS).
      end_spline();
      begin_spline();
    }
  }
  pending.vel = std::numeric_limits<double>::quiet_NaN();
  if (segment_vel) {
    Values v;
    v.number_value = vel_requested;
    if (render(Stmt::vel, v) != vel_written)
      pending.vel = vel_requested;
  }
  pending.motion = m;
  pending.start = last_p;
  pending.start_tangent = tangent;
  pending.index = motion_count + 1;
  have_pending = true;
  ++spline_points;
}

void KrlWriter::Impl::ptp_axes(const AxisValues& axes) {
  Values v;
  v.axes = &axes;
  put(Stmt::ptp_axes, v);
}

void KrlWriter::Impl::bco_ptp(const AxisValues& axes) {
  Values v;
  v.axes = &axes;
  put(tpl.has(Stmt::bco_ptp) ? Stmt::bco_ptp : Stmt::ptp_axes, v);
}

KrlWriter::Impl::Values KrlWriter::Impl::pose_values(const KrlMotion& m) {
  Values v;
  v.axes = &m.axes;
  const Eigen::Vector3d p = m.T_base_tcp.translation();
  for (int i = 0; i < 3; ++i)
    v.xyz[i] = p[i];
  v.abc = abc_from_rotation(m.T_base_tcp.linear());
  if (!m.T_base_tcp.linear().allFinite()) {
    v.abc.a_deg = v.abc.b_deg = v.abc.c_deg = std::numeric_limits<double>::quiet_NaN();
  }
  v.st = m.status_turn;
  return v;
}

void KrlWriter::Impl::flush_velocity() {
  require_velocity();
  Values v;
  v.number_value = vel_requested;
  std::string text = render(Stmt::vel, v);
  if (text != vel_written) {
    end_spline();
    put(src_out, out_index, text);
    vel_written = std::move(text);
    vel_in_force = vel_requested;
  }
}

void KrlWriter::Impl::require_velocity() const {
  if (std::isnan(vel_requested)) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}', motion {}: a feed move before any feed rate "
                            "(velocity() was never called); refusing to write a LIN at the "
                            "controller's default speed",
                            info.name, motion_count + 1));
  }
}

// A part starts where the previous one ended, in the same state, so it can run alone. A part
// that continues a cut restates only the frames: a tool's $TOOL and $LOAD are what KUKA's own
// inline motions set between blended motions (BAS (#FRAMES)); the spindle and coolant are the
// cell's outputs, which may stop the advance run, and stay as they are.
void KrlWriter::Impl::restate(bool continued) {
  bool has_frames = false;
  for (const krl::SkeletonLine& l : *module_src)
    has_frames = has_frames || l.block == krl::Ph::frames;
  // {frames} in the part's header has set $TOOL already. A set without tool_select restates the
  // tool change itself: never in a cut.
  if (!has_frames && (!continued || tpl.has(Stmt::tool_select)))
    put(src_out, out_index, tool_state);
  vel_written.clear();  // the part's INI reset $VEL.CP; a continued part states it again
  if (continued)
    return;
  put(src_out, out_index, spindle_state);
  put(src_out, out_index, coolant_state);
  bco_ptp(last_axes);
}

KrlWriter::KrlWriter(const KrlTemplateSet& templates, const KrlProgramInfo& info)
    : impl_(std::make_unique<Impl>(templates, info)) {
  Impl& w = *impl_;
  check_program_info(info);
  // The set may have been built by hand rather than loaded: check it as the loader does.
  w.tpl = krl::compile_templates(templates);
  for (const krl::SkeletonLine& l : w.tpl.src)
    w.src_has_frames = w.src_has_frames || l.block == krl::Ph::frames;
  check_frames(templates, w.tpl, info, w.src_has_frames);
  w.spl = templates.spline && w.tpl.has(Stmt::spline_spl) && info.spline_tolerance_mm > 0.0;
  w.segment_vel = w.spl && w.tpl.has(Stmt::spline_lin_vel) && w.tpl.has(Stmt::spline_spl_vel);
  w.budget = info.max_file_bytes > 0        ? info.max_file_bytes
             : templates.max_file_bytes > 0 ? templates.max_file_bytes
                                            : kDefaultMaxFileBytes;
  if (w.tpl.wants_date) {
    // Only on request: a date makes the output differ from run to run.
    w.date = utc_date_now();
  }
  check_output_dir(info.output_dir);
  w.lock = OutputLock(info.output_dir, info.name);

  // The first file now: an unwritable directory shows at once, not after the whole path.
  if (info.motions_per_file > 0)
    w.next_part();
  else
    w.open_module(info.name);
}

std::string krl_program_name_problem(std::string_view name) {
  return krl::identifier_problem(name);
}

KrlWriter::~KrlWriter() {
  if (!impl_)
    return;
  Impl& w = *impl_;
  if (w.src_out)
    std::fclose(w.src_out);
  // A program that was not finished must not look finished: remove what is not renamed.
  for (const Impl::File& f : w.files) {
    if (!f.renamed)
      remove_temporary(f.temp);
  }
}

void KrlWriter::motion(const KrlMotion& m) {
  Impl& w = *impl_;
  if (w.finished || w.prepared)
    throw Error(ErrorCode::internal, "KRL writer: motion() after prepare() or finish()");

  int mask = 0;
  for (int n = 1; n <= 6; ++n)
    mask |= std::isnan(m.axes.external(n)) ? 0 : 1 << (n - 1);
  if (w.ext_mask < 0)
    w.ext_mask = mask;
  if (mask != w.ext_mask) {
    throw Error(ErrorCode::internal,
                fmt::format("program '{}', motion {}: external axes (mask {:06b}) differ from "
                            "those of the first motion ({:06b})",
                            w.info.name, w.motion_count + 1, mask, w.ext_mask));
  }

  if (w.info.motions_per_file > 0 && w.motions_in_module == w.info.motions_per_file) {
    w.end_part();
  } else if (w.last_in_air && w.part_nearly_full()) {
    // Out of the material (where a rapid or an approach ended; a rapid may start in the cut, a
    // drill's retract from the hole's bottom): the part ends here rather than later in a cut,
    // where its successor's first PTP would stop the tool.
    w.end_part();
  } else {
    // A motion with what may come with it: a CL line comment, $VEL.CP, a spline block's ends.
    w.ensure_room(1024);
  }
  if (w.info.cl_line_every > 0 && m.cl_line > 0 && w.motion_count % w.info.cl_line_every == 0) {
    Impl::Values v;
    v.integer = m.cl_line;
    w.put_in_block(w.render(Stmt::cl_line, v));
  }
  w.joined_smoothly = false;

  if (!w.have_last) {
    // The first motion of a program is always a full-axis PTP: it fixes the posture, and the
    // controller's BCO run needs a PTP. The robot may stand anywhere: the set's bco_ptp says so
    // and slows it.
    w.bco_ptp(m.axes);
  } else {
    switch (m.kind) {
      case KrlMotionKind::ptp_axes:
        w.end_spline();
        w.ptp_axes(m.axes);
        break;
      case KrlMotionKind::rapid:
        w.end_spline();
        w.put(Stmt::rapid, w.pose_values(m));
        break;
      case KrlMotionKind::lin: {
        // With speeds per segment, a new $VEL.CP is written only between blocks.
        if (w.segment_vel && w.in_spline)
          w.require_velocity();
        else
          w.flush_velocity();
        if (w.spl) {
          w.spline_feed_move(m);
          break;
        }
        const Impl::Values v = w.pose_values(m);
        if (w.t.spline) {
          if (w.in_spline && w.spline_points == w.t.max_spline_points)
            w.end_spline();
          if (!w.in_spline) {
            w.put(Stmt::spline_begin, Impl::Values{});
            w.in_spline = true;
            w.spline_points = 0;
          }
          w.put(Stmt::spline_lin, v);
          ++w.spline_points;
        } else {
          w.put(Stmt::lin, v);
        }
        break;
      }
    }
  }
  w.last_axes = m.axes;
  w.last_p = m.T_base_tcp.translation();
  w.last_in_air = m.in_air;
  w.last_cl_line = m.cl_line;
  w.have_last = true;
  ++w.motion_count;
  ++w.motions_in_module;
}

void KrlWriter::velocity(double vel_m_per_s) {
  if (!std::isfinite(vel_m_per_s) || vel_m_per_s <= 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}': velocity {} m/s; a feed rate must be > 0",
                            impl_->info.name, vel_m_per_s));
  }
  impl_->vel_requested = vel_m_per_s;
}

void KrlWriter::tool_change(const KrlToolChange& change) {
  Impl& w = *impl_;
  const std::string clean = one_line(change.name);
  const std::string tool = one_line(change.tool);
  if (tool.empty())
    throw Error(ErrorCode::bad_input, "a tool change needs the right-hand side of $TOOL");
  const bool manual = w.info.tool_change_routine.empty();
  if (manual && !w.tpl.has(Stmt::tool_change_manual) && w.tpl.has(Stmt::tool_select)) {
    throw Error(ErrorCode::bad_input,
                "template set '" + w.t.name +
                    "' has no tool_change_manual statement, and the cell names no tool change "
                    "routine (<controller tool-change-routine=...>)",
                SourceLocation{w.t.source_file, 0, 0});
  }
  w.ensure_room(static_cast<long>(clean.size() + 512));
  w.end_spline();
  Impl::Values v;
  v.integer = change.number;
  v.tool_name = clean;
  v.tool = tool;
  v.tool_data = change.tool_data;
  v.load_data = change.load_data > 0 ? change.load_data : change.tool_data;
  v.routine = w.info.tool_change_routine;
  // Sets without the newer statements: tool_change alone, as before them.
  const Stmt how =
      manual && w.tpl.has(Stmt::tool_change_manual) ? Stmt::tool_change_manual : Stmt::tool_change;
  w.put(w.src_out, w.out_index, w.render(how, v));
  w.current_tool = {tool, change.tool_data, v.load_data};
  if (w.tpl.has(Stmt::tool_select)) {
    w.tool_state = w.render(Stmt::tool_select, v);
    w.put(w.src_out, w.out_index, w.tool_state);
  } else {
    w.tool_state = w.render(Stmt::tool_change, v);
  }
}

void KrlWriter::dwell(double seconds) {
  Impl& w = *impl_;
  if (!std::isfinite(seconds) || seconds < 0.0) {
    throw Error(ErrorCode::bad_input, fmt::format("program '{}': a dwell of {} s; it must be >= 0",
                                                  w.info.name, seconds));
  }
  if (!w.tpl.has(Stmt::dwell)) {
    throw Error(ErrorCode::bad_input,
                "template set '" + w.t.name +
                    "' has no dwell statement, but the program asks for a dwell (a drilling "
                    "cycle's DWELL)",
                SourceLocation{w.t.source_file, 0, 0});
  }
  w.ensure_room(256);
  w.end_spline();
  Impl::Values v;
  v.number_value = seconds;
  w.put(Stmt::dwell, v);
}

bool KrlWriter::has_spl() const {
  return impl_->spl;
}

bool KrlWriter::take_rate_segment(long index, double& vel_m_per_s) {
  auto& q = impl_->rate_segments;
  while (!q.empty() && q.front().first < index)
    q.pop_front();
  if (q.empty() || q.front().first != index)
    return false;
  vel_m_per_s = q.front().second;
  q.pop_front();
  return true;
}

void KrlWriter::end_block() {
  impl_->end_spline();
}

bool KrlWriter::joined_smoothly() const {
  return impl_->joined_smoothly;
}

bool KrlWriter::has_circ() const {
  return impl_->tpl.has(Stmt::circ) && !impl_->t.spline;
}

void KrlWriter::circ(const KrlMotion& aux, const KrlMotion& end) {
  Impl& w = *impl_;
  if (!has_circ())
    throw Error(ErrorCode::internal, "KRL writer: circ() with a set that has no circ statement");
  if (!w.have_last)
    throw Error(ErrorCode::internal, "KRL writer: a CIRC cannot be the first motion");
  w.ensure_room(2048);
  if (w.info.cl_line_every > 0 && end.cl_line > 0 && w.motion_count % w.info.cl_line_every == 0) {
    Impl::Values c;
    c.integer = end.cl_line;
    w.put(Stmt::cl_line, c);
  }
  w.flush_velocity();
  Impl::Values v = w.pose_values(end);
  const Eigen::Vector3d p = aux.T_base_tcp.translation();
  for (int i = 0; i < 3; ++i)
    v.aux[i] = p[i];
  w.put(Stmt::circ, v);
  w.last_axes = end.axes;
  w.last_in_air = end.in_air;
  w.last_cl_line = end.cl_line;
  ++w.motion_count;
  ++w.motions_in_module;
}

void KrlWriter::spindle(double rpm, bool clockwise) {
  Impl& w = *impl_;
  if (!std::isfinite(rpm) || rpm < 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}': spindle speed {} rpm; it must be >= 0 (0: off)",
                            w.info.name, rpm));
  }
  w.ensure_room(512);
  w.end_spline();
  Impl::Values v;
  if (rpm == 0.0) {
    w.spindle_state.clear();
    w.put(Stmt::spindle_off, v);
    return;
  }
  v.number_value = rpm;
  v.direction = clockwise ? "CW" : "CCW";
  v.clockwise = clockwise ? "TRUE" : "FALSE";
  w.spindle_state = w.render(Stmt::spindle_on, v);
  w.put(w.src_out, w.out_index, w.spindle_state);
}

void KrlWriter::coolant(bool on, const std::string& mode) {
  Impl& w = *impl_;
  w.ensure_room(static_cast<long>(mode.size() + 512));
  w.end_spline();
  Impl::Values v;
  const std::string clean = one_line(mode);
  v.mode = clean;
  const std::string text = w.render(on ? Stmt::coolant_on : Stmt::coolant_off, v);
  w.coolant_state = on ? text : std::string();
  w.put(w.src_out, w.out_index, text);
}

void KrlWriter::comment(const std::string& text) {
  Impl& w = *impl_;
  Impl::Values v;
  const std::string clean = one_line(text);
  w.ensure_room(static_cast<long>(clean.size() + 256));
  v.text = clean;
  w.put_in_block(w.render(Stmt::comment, v));  // a comment may stand inside a spline block
}

void KrlWriter::literal(const std::string& text) {
  Impl& w = *impl_;
  if (text.find_first_of("\r\n") != std::string::npos) {
    throw Error(ErrorCode::bad_input,
                "program '" + w.info.name + "': a literal KRL statement must be one line");
  }
  w.ensure_room(static_cast<long>(text.size() + 256));
  w.end_spline();
  Impl::Values v;
  v.text = text;
  w.put(Stmt::literal, v);
}

void KrlWriter::prepare() {
  Impl& w = *impl_;
  if (w.prepared)
    return;
  w.close_module();
  if (!w.parts.empty())
    w.write_main_program();
  w.split.parts = static_cast<int>(w.parts.size());
  w.split.program_bytes = 0;
  for (const Impl::File& f : w.files)
    w.split.program_bytes += static_cast<long>(fs::file_size(f.temp));
  w.prepared = true;
}

const KrlSplitReport& KrlWriter::split() const {
  return impl_->split;
}

std::vector<std::string> KrlWriter::finish() {
  Impl& w = *impl_;
  if (w.finished)
    throw Error(ErrorCode::internal, "KRL writer: finish() called twice");
  prepare();
  w.rename_files();
  w.finished = true;
  w.lock = OutputLock();  // the program is in place: another writer may take it now

  std::vector<std::string> written;
  const auto src = [&](const std::string& name) {
    return (fs::path(w.info.output_dir) / (name + ".src")).string();
  };
  written.push_back(src(w.info.name));
  for (const std::string& part : w.parts)
    written.push_back(src(part));
  return written;
}

int KrlWriter::motions() const {
  return static_cast<int>(impl_->motion_count);
}

}  // namespace redpost
