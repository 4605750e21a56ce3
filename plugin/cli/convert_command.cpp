// `redpost convert`: a CL file (APT/CLDATA or NX CLSF) in, a KRL program out, through the C ABI
// (redpost.h) like every other host, so that the command and the other hosts cannot drift apart.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "redpost.h"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/output_target.hpp"
#include "report/convert_report.hpp"

namespace redpost::cli {

namespace {

// A command-line argument the ABI never sees (the --placement text), reported as bad input.
struct BadArgument {
  std::string message;
};

struct ConvertOptions {
  std::string input;
  std::string cell_path;
  std::string krl_path;
  std::string output_dir;
  std::string name;
  std::string joints_csv;
  std::string report_html;  // --report: an HTML report of the run; empty: none
  std::string placement;    // "x,y,z,a,b,c" of the CL frame in the cell's {B}
  std::string base;         // empty: BASE_DATA[n] of the cell's <controller base-data>, or 1
  std::string tool = "TOOL_DATA[1]";
  std::string tools_path;  // --tools: a tool table file
  std::string msys = "ignore";
  std::string clearance;  // --clearance Z (mm); empty: none
  double rapid_velocity_m_per_s = 0.25;
  long max_bytes = -1;  // -1: not given
  double apo_mm = 0.5;
  int split = 0;
  int cl_line_every = 50;
  double chordal_tolerance_mm = 0.01;
  double fit_tolerance_mm = 0.01;
  int threads = 0;  // one per core, at most 8 (issue 47)
  double fit_angle_tolerance_deg = 0.1;
  std::string plan = "global";
  std::string preset = "smooth";
  double keyframe_spacing_mm = 20.0;
  std::vector<std::string> locks;  // --lock E1=500, --lock E2
  // The deflection (docs/deflection.md): --predict-deflection, --compensate, --cutting FILE.
  bool predict_deflection = false;
  bool compensate = false;
  std::string cutting_path;
  double deflection_tolerance_mm = 0.05;
  // Collisions (docs/collision.md): the set-up's STL files in the CL frame, and the margin.
  std::vector<std::string> fixtures;
  std::string part;
  double collision_margin_mm = 5.0;
  bool no_collision = false;
  std::vector<const char*> fixture_pointers;  // into `fixtures`, for rp_options
  bool quiet = false;
};

// --lock E1=500 or --lock E2: the axis number and the value (NaN: none given).
void parse_lock(const std::string& text, rp_options& o) {
  const std::size_t eq = text.find('=');
  const std::string axis = text.substr(0, eq);
  if (axis.size() != 2 || (axis[0] != 'E' && axis[0] != 'e') || axis[1] < '1' || axis[1] > '6')
    throw BadArgument{"--lock '" + text + "': name an external axis E1..E6, e.g. --lock E1=500"};
  const int k = axis[1] - '1';
  o.lock_mask |= 1u << k;
  if (eq == std::string::npos)
    return;
  const std::string value = text.substr(eq + 1);
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(v))
    throw BadArgument{"--lock '" + text + "': the value is not a number (mm or deg)"};
  o.lock_value[k] = v;
}

// A KRL identifier from a file name: letters, digits and '_', a letter first, short enough to
// take the _P001 suffix of a split program.
// The name made from the input file's: 19 characters leave room for the part suffix.
constexpr size_t kDerivedNameLength = 19;

std::string program_name_from(const std::string& path) {
  std::string stem = std::filesystem::path(path).stem().string(), out;
  for (char c : stem) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    out += ok ? c : '_';
  }
  if (out.empty() || !std::isalpha(static_cast<unsigned char>(out[0])))
    out = "P" + out;
  if (out.size() > kDerivedNameLength) {
    fmt::print(stderr,
               "warning: the program name '{}' is the input file's name cut to {} characters "
               "(a KRL name has at most 24, and 5 stay free for the parts _P001, ... of a split "
               "program); give --name to choose it\n",
               out.substr(0, kDerivedNameLength), kDerivedNameLength);
    out.resize(kDerivedNameLength);
  }
  return out;
}

// A program name the library refuses, said with where it came from: --name, or the input.
std::string program_name_message(const ConvertOptions& opt, const std::string& message) {
  if (message.rfind("program name '", 0) != 0)
    return message;
  if (!opt.name.empty())
    return "--name: " + message + "; choose another";
  return message + " (it was made from the input file's name, " +
         std::filesystem::path(opt.input).filename().string() + "); give another with --name";
}

// "x,y,z,a,b,c" -> six numbers (mm, deg).
void parse_placement(const std::string& text, double v[6]) {
  const std::string message =
      "redpost: --placement takes six numbers x,y,z,a,b,c (mm and deg), got '" + text + "'";
  int n = 0;
  size_t i = 0;
  while (i <= text.size() && n < 7) {
    const size_t j = text.find(',', i);
    const std::string token = text.substr(i, j == std::string::npos ? std::string::npos : j - i);
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (token.empty() || end == token.c_str() || *end != '\0' || !std::isfinite(x) || n == 6)
      throw BadArgument{message};
    v[n++] = x;
    if (j == std::string::npos)
      break;
    i = j + 1;
  }
  if (n != 6)
    throw BadArgument{message};
}

// Values as the robot programmer reads them: the ABI gives controller units for mapped joints
// (A2 -90 deg), DH degrees or mm otherwise, with the ends already in controller order.
std::string joint_value_text(const rp_joint_range_info& j, double v) {
  return fmt::format(j.prismatic ? "{:.1f} mm" : "{:.2f} deg", v);
}

// The deflection per CL operation (docs/deflection.md), when it was predicted.
void print_deflection(const rp_session* session) {
  rp_deflection_summary d{};
  d.struct_size = sizeof d;
  if (rp_deflection_summary_get(session, &d) != RP_OK || d.mode == RP_DEFLECTION_OFF)
    return;
  const bool comp = d.mode == RP_DEFLECTION_COMPENSATE;
  fmt::print(
      "deflection under the cutting force ({}; tolerance {:g} mm along the wall's "
      "normal):\n",
      comp ? "compensated" : "predicted", d.tolerance_mm);
  fmt::print("  {:<20} {:>7} {:>9} {:>9} {:>10} {:>10} {:>7}{}\n", "operation", "moves", "max mm",
             "rms mm", "normal max", "normal rms", "over",
             comp ? "   after: normal max  over" : "");
  for (int i = 0; i < d.operations; ++i) {
    rp_deflection_info f{};
    f.struct_size = sizeof f;
    if (rp_deflection_get(session, i, &f) != RP_OK)
      break;
    const std::string name = *f.operation ? f.operation : "(no operation)";
    fmt::print("  {:<20} {:>7} {:>9.3f} {:>9.3f} {:>10.3f} {:>10.3f} {:>7}", name, f.motions,
               f.max_mm, f.rms_mm, f.max_normal_mm, f.rms_normal_mm, f.over_tolerance);
    if (comp)
      fmt::print("   {:>17.4f} {:>5}", f.max_residual_normal_mm, f.over_tolerance_after);
    fmt::print("\n");
  }
  if (d.operations == 0)
    fmt::print(
        "  no cutting move with a load (plunges, drilling and moves with the spindle off "
        "have none)\n");
  if (comp) {
    fmt::print("  fixed point: {} extra iteration(s) over the program, at most {} for one move\n",
               d.compensation_iterations, d.max_compensation_iterations);
  }
}

// The collision check (docs/collision.md): what was checked and the least clearance.
void print_collisions(const rp_session* session) {
  rp_collision_summary c{};
  c.struct_size = sizeof c;
  if (rp_collision_get(session, &c) != RP_OK)
    return;
  if (!c.checked) {
    fmt::print(
        "collisions: not checked (no bodies: the cell has no <collision>, no tool "
        "geometry, no --fixture or --part)\n");
    return;
  }
  const std::string least = std::isfinite(c.least_clearance_mm)
                                ? fmt::format("{:.1f} mm ({}, CL line {})", c.least_clearance_mm,
                                              c.least_clearance_pair, c.least_clearance_line)
                                : fmt::format("more than {:g} mm", c.margin_mm + 25.0);
  fmt::print(
      "collisions: {} bodies, {} pairs, at least {:g} mm apart along every motion "
      "(proven: {:.1f} mm); closest {}\n",
      c.bodies, c.pairs, c.margin_mm, c.proven_clearance_mm, least);
}

// The time model (docs/timing.md): cycle time, the axes against their limits, and the
// stretches where an axis keeps the feed below the CL file's.
void print_timing(const rp_session* session) {
  rp_timing t{};
  t.struct_size = sizeof t;
  if (rp_timing_get(session, &t) != RP_OK)
    return;
  std::string line = "cycle time " + run_report::duration_text(t.cycle_time_s);
  if (t.feed_time_s > 0.0) {
    line += fmt::format(
        " (cutting {}, {:+.1f} % on the CL feeds' {})", run_report::duration_text(t.cutting_time_s),
        100.0 * (t.cutting_time_s / t.feed_time_s - 1.0), run_report::duration_text(t.feed_time_s));
  }
  if (t.untimed_tool_changes > 0)
    line += fmt::format(", without the time of {} tool change(s)", t.untimed_tool_changes);
  fmt::print("{}\n", line);
  if (t.interpolation_cycle_s > 0.0 && t.cp_motions > 0) {
    // The controller's clock (docs/timing.md, "The interpolation cycle").
    fmt::print(
        "interpolation cycle {:g} ms: {} of {} CP motion(s) last less than a cycle at their "
        "$VEL.CP ({:.0f} %, shortest {:.1f} ms at CL line {}); {} slowed by the motion rate{}, {} "
        "by the look-ahead\n",
        t.interpolation_cycle_s * 1000.0, t.below_cycle_motions, t.cp_motions,
        100.0 * static_cast<double>(t.below_cycle_motions) / static_cast<double>(t.cp_motions),
        t.shortest_motion_s * 1000.0, t.shortest_motion_line, t.rate_limited_motions,
        t.rate_slowed_motions > 0
            ? fmt::format(" ({} written with the $VEL.CP at which they last a cycle)",
                          t.rate_slowed_motions)
            : std::string(),
        t.lookahead_limited_motions);
  }
  if (t.reduced_moves < t.reducible_points) {
    fmt::print(
        "point reduction: {} cutting point(s) tracked as {} move(s) ({:.1f} x fewer){}\n",
        t.reducible_points, t.reduced_moves,
        static_cast<double>(t.reducible_points) /
            static_cast<double>(std::max(t.reduced_moves, 1L)),
        t.reduced_arcs > 0 ? fmt::format(", {} of them arcs", t.reduced_arcs) : std::string());
  }
  if (t.plan_windows > 0) {
    fmt::print(
        "whole-path plan: {} window(s), {} with the external axes held (faster or better "
        "conditioned than moving them), {} tracked pose by pose, {} IK solutions\n",
        t.plan_windows, t.plan_still_windows, t.plan_fallback_windows, t.plan_ik_evaluations);
  }
  if (!t.axis_speeds_known) {
    fmt::print("axis speeds: not checked (the cell gives none)\n");
    return;
  }
  rp_joint_range_info j{};
  std::string peak_axis = "-";
  if (t.peak_speed_joint >= 0 && rp_joint_range(session, t.peak_speed_joint, &j) == RP_OK)
    peak_axis = std::string(j.axis_name) + " (" + j.name + ")";
  fmt::print(
      "axis speeds: at most {:.2f} of the limit ({}, CL line {}); {} motion(s) written "
      "with a lower $VEL.CP\n",
      t.peak_speed_fraction, peak_axis, t.peak_speed_line, t.slowed_motions);
  if (t.feed_limits == 0)
    return;
  fmt::print(
      "where an axis or the controller's clock keeps the feed 5 % or more below the CL "
      "file's ({}):\n",
      t.feed_limits);
  constexpr int kShown = 12;
  for (int i = 0; i < t.feed_limits_listed && i < kShown; ++i) {
    rp_feed_limit_info f{};
    f.struct_size = sizeof f;
    if (rp_feed_limit(session, i, &f) != RP_OK)
      break;
    const std::string lines = f.first_line == f.last_line
                                  ? fmt::format("CL {}", f.first_line)
                                  : fmt::format("CL {}-{}", f.first_line, f.last_line);
    fmt::print("  {:<16} {:>3} {:<10} {:<18} {:.0f} of {:.0f} mm/min, {} motion(s)\n", lines,
               f.axis_name, f.joint_name, f.limit, f.lowest_mm_per_min, f.asked_mm_per_min,
               f.motions);
  }
  if (t.feed_limits > kShown)
    fmt::print("  ... and {} more (all in the report, --report)\n", t.feed_limits - kShown);
}

void print_summary(const rp_session* session, double seconds) {
  rp_summary s{};
  rp_summary_get(session, &s);
  fmt::print("poses {} (motions written {}), {:.2f} s, {:.0f} poses/s\n", s.poses, s.motions,
             seconds, seconds > 0 ? s.poses / seconds : 0.0);
  fmt::print("lowest 1/kappa_F of the arm: {:.3f} (CL line {})\n", s.lowest_inv_condition,
             s.lowest_inv_condition_line);
  fmt::print("{:<12} {:>6} {:>26} {:>26}\n", "joint", "axis", "range used",
             "smallest margin (low/high)");
  rp_joint_range_info r{};
  for (int i = 0; rp_joint_range(session, i, &r) == RP_OK; ++i) {
    fmt::print("{:<12} {:>6} {:>26} {:>26}\n", r.name, r.axis_name,
               joint_value_text(r, r.lowest) + " .. " + joint_value_text(r, r.highest),
               joint_value_text(r, r.margin_lower) + " / " + joint_value_text(r, r.margin_upper));
  }
  print_timing(session);
  print_collisions(session);
  print_deflection(session);
  for (int i = 0; const char* f = rp_output_file(session, i); ++i)
    fmt::print("wrote {}\n", f);
}

// Both handles are released on every path (rp_free of an unclosed session removes its
// temporary files).
struct Handles {
  rp_reader* reader = nullptr;
  rp_session* session = nullptr;
  ~Handles() {
    rp_reader_free(reader);
    rp_free(session);
  }
};

// The session's messages start with the event number ("event 1204: part.apt:1180: ..."), which
// helps a host that makes its own events; here the file and line say more, and the messages
// stay those the command always printed.
std::string without_event_number(const char* message) {
  const std::string m = message;
  const std::string prefix = "event ";
  if (m.compare(0, prefix.size(), prefix) != 0)
    return m;
  size_t i = prefix.size();
  while (i < m.size() && std::isdigit(static_cast<unsigned char>(m[i])))
    ++i;
  return i > prefix.size() && m.compare(i, 2, ": ") == 0 ? m.substr(i + 2) : m;
}

// "redpost: message" and the exit code of the status: 2 for what the user can fix, 3 for a bug.
int report(rp_status status, const std::string& message) {
  if (status == RP_ERR_INTERNAL) {
    fmt::print(stderr, "redpost: internal error: {}\n", message);
    return 3;
  }
  fmt::print(stderr, "redpost: {}\n", message);
  return kExitBadInput;
}

// Outputs that would destroy an input or each other, and a --report that is not a regular file,
// are refused before anything is read (the library checks the program and the joints CSV too,
// but does not know the report, and names the options as a C host sees them).
void check_outputs(const ConvertOptions& opt, const std::string& name) {
  if (!opt.report_html.empty())
    check_output_target(opt.report_html, "--report");
  const auto program_file = [&](const char* ext) {
    return (std::filesystem::path(opt.output_dir) / (name + ext)).string();
  };
  check_distinct_files({{"the CL input", opt.input},
                        {"--cell", opt.cell_path},
                        {"--krl", opt.krl_path},
                        {"--tools", opt.tools_path},
                        {"--cutting", opt.cutting_path}},
                       {{"the program's .src", program_file(".src")},
                        {"the program's .dat", program_file(".dat")},
                        {"--joints-csv", opt.joints_csv},
                        {"--report", opt.report_html}});
}

// The session's options from the command line; `o` points into `opt` and `name`.
void session_options(ConvertOptions& opt, const std::string& name, rp_options& o) {
  double placement[6] = {0, 0, 0, 0, 0, 0};
  if (!opt.placement.empty())
    parse_placement(opt.placement, placement);

  rp_options_init(&o);
  o.cell_path = opt.cell_path.c_str();
  o.krl_path = opt.krl_path.empty() ? nullptr : opt.krl_path.c_str();
  o.output_dir = opt.output_dir.c_str();
  o.program_name = name.c_str();
  o.joints_csv_path = opt.joints_csv.empty() ? nullptr : opt.joints_csv.c_str();
  o.source_name = opt.input.c_str();
  o.base = opt.base.empty() ? nullptr : opt.base.c_str();
  o.tools_path = opt.tools_path.empty() ? nullptr : opt.tools_path.c_str();
  if (!opt.clearance.empty()) {
    char* end = nullptr;
    o.clearance_z_mm = std::strtod(opt.clearance.c_str(), &end);
    if (end == opt.clearance.c_str() || *end != '\0' || !std::isfinite(o.clearance_z_mm)) {
      throw BadArgument{"--clearance '" + opt.clearance +
                        "': the clearance height is not a finite number of mm"};
    }
    o.has_clearance = 1;
  }
  o.rapid_velocity_m_per_s = opt.rapid_velocity_m_per_s;
  if (opt.max_bytes != -1 && opt.max_bytes < 16 * 1024) {
    throw BadArgument{
        fmt::format("--max-bytes {}: a program file must be allowed more; the byte "
                    "limit must be at least 16384 (16 KiB)",
                    opt.max_bytes)};
  }
  o.max_file_bytes = opt.max_bytes == -1 ? 0 : opt.max_bytes;
  o.tool = opt.tool.c_str();
  o.has_placement = opt.placement.empty() ? 0 : 1;
  std::copy(placement, placement + 6, o.placement);
  o.apo_mm = opt.apo_mm;
  o.motions_per_file = opt.split;
  o.cl_line_every = opt.cl_line_every;
  o.chordal_tolerance_mm = opt.chordal_tolerance_mm;
  o.fit_tolerance_mm = opt.fit_tolerance_mm;
  o.fit_angle_tolerance_deg = opt.fit_angle_tolerance_deg;
  o.plan = opt.plan == "local" ? RP_PLAN_LOCAL : RP_PLAN_GLOBAL;
  o.plan_preset = opt.preset == "stiff"  ? RP_PLAN_STIFF
                  : opt.preset == "fast" ? RP_PLAN_FAST
                                         : RP_PLAN_SMOOTH;
  o.keyframe_spacing_mm = opt.keyframe_spacing_mm;
  o.plan_threads = opt.threads;
  // With threads to spare the file is read on this thread while the session plans on its own
  // (rp_options.pipeline), the program the same bytes.
  o.pipeline = opt.threads >= 2 || (opt.threads == 0 && std::thread::hardware_concurrency() >= 2);
  for (const std::string& l : opt.locks)
    parse_lock(l, o);
  // --cutting alone asks for the prediction: the conditions have no other use.
  o.deflection = opt.compensate                                        ? RP_DEFLECTION_COMPENSATE
                 : opt.predict_deflection || !opt.cutting_path.empty() ? RP_DEFLECTION_PREDICT
                                                                       : RP_DEFLECTION_OFF;
  o.cutting_path = opt.cutting_path.empty() ? nullptr : opt.cutting_path.c_str();
  o.deflection_tolerance_mm = opt.deflection_tolerance_mm;
  o.msys = opt.msys == "apply" ? RP_MSYS_APPLY : RP_MSYS_IGNORE;
  o.report_path = opt.report_html.empty() ? nullptr : opt.report_html.c_str();
  o.fixture_paths = opt.fixture_pointers.empty() ? nullptr : opt.fixture_pointers.data();
  o.fixture_count = static_cast<int>(opt.fixture_pointers.size());
  o.part_path = opt.part.empty() ? nullptr : opt.part.c_str();
  o.collision_margin_mm = opt.collision_margin_mm;
  o.collision_check = opt.no_collision ? 0 : 1;
}

int run_convert(ConvertOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  // The report is written after the program: a folder that cannot take it must stop the run
  // before the conversion, not after it with the program written and exit code 2.
  if (!opt.report_html.empty())
    check_output_folder(opt.report_html, "--report");
  const std::string name = opt.name.empty() ? program_name_from(opt.input) : opt.name;
  opt.fixture_pointers.clear();
  for (const std::string& f : opt.fixtures)
    opt.fixture_pointers.push_back(f.c_str());
  rp_options o;
  session_options(opt, name, o);
  check_outputs(opt, name);
  Handles h;
  // The input first: a FIFO without a writer blocks here, before any output file exists.
  rp_reader_options ro;
  rp_reader_options_init(&ro);
  ro.chordal_tolerance_mm = opt.chordal_tolerance_mm;
  // The toolpath as the file says it: the session expands cycles, NURBS and MSYS as it does NX's
  // events, and writes a CIRC where the set has one, chords otherwise.
  ro.toolpath_events = 1;
  if (const rp_status st = rp_reader_open_ex(opt.input.c_str(), &ro, &h.reader); st != RP_OK) {
    return report(st, rp_last_error(nullptr));
  }
  if (const rp_status st = rp_open(&o, &h.session); st != RP_OK)
    return report(st, program_name_message(opt, rp_last_error(nullptr)));

  const bool progress = !opt.quiet && ::isatty(STDERR_FILENO) == 1;
  auto last_report = std::chrono::steady_clock::now();
  rp_event event;
  long events = 0;
  for (;;) {
    int more = 0;
    if (const rp_status st = rp_reader_next(h.reader, &event, &more); st != RP_OK) {
      // An event before the broken line that failed on the session's thread is the error, as
      // it is without the pipeline.
      if (const rp_status earlier = rp_sync(h.session); earlier != RP_OK)
        return report(earlier, without_event_number(rp_last_error(h.session)));
      return report(st, rp_reader_last_error(h.reader));
    }
    if (!more)
      break;
    if (const rp_status st = rp_session_event(h.session, &event); st != RP_OK)
      return report(st, without_event_number(rp_last_error(h.session)));
    if (progress && (++events & 1023) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report > std::chrono::milliseconds(500)) {
        rp_summary s{};
        rp_summary_get(h.session, &s);
        fmt::print(stderr, "\r{} poses, CL line {}   ", s.poses, event.line);
        std::fflush(stderr);
        last_report = now;
      }
    }
  }
  if (progress)
    fmt::print(stderr, "\r{:40}\r", "");
  // The reader's warnings (about the file itself) are the session's first ones.
  for (int i = 0; const char* w = rp_reader_warning(h.reader, i); ++i) {
    if (const rp_status st = rp_warn(h.session, w); st != RP_OK)
      return report(st, rp_last_error(h.session));
  }
  // Everything is written and flushed before anything is renamed: the report too (the library
  // writes it), so that a full disk or a bad report path stops the run with an old program of
  // the name still whole.
  if (const rp_status st = rp_prepare(h.session); st != RP_OK)
    return report(st, without_event_number(rp_last_error(h.session)));
  for (int i = 0; const char* w = rp_warning(h.session, i); ++i)
    fmt::print(stderr, "warning: {}\n", w);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (const rp_status st = rp_close(h.session); st != RP_OK)
    return report(st, rp_last_error(h.session));
  if (!opt.quiet)
    print_summary(h.session, seconds);
  return kExitOk;
}

}  // namespace

Runner add_convert_command(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  CLI::App* c = app.add_subcommand(
      "convert", "Convert a CL file (APT/CLDATA or NX CLSF) into a KRL program (.src/.dat).");
  c->add_option("input", opt->input, "CL file")->required();
  c->add_option("--cell", opt->cell_path, "Cell definition (XML)")->required();
  c->add_option("--krl", opt->krl_path, "KRL template set (XML); default krc4_lin");
  c->add_option("-o,--output", opt->output_dir, "Output directory (must exist)")->required();
  c->add_option("--name", opt->name,
                "Program name (KRL identifier, at most 24 characters); default from the input");
  c->add_option("--joints-csv", opt->joints_csv,
                "Write one row per motion: pose, CL line, joints (DH units), controller axes");
  c->add_option("--report", opt->report_html,
                "Write an HTML report of the run: joints, 1/kappa_F, external axes, feed, "
                "toolpath views and the margins to the limits");
  c->add_option("--placement", opt->placement,
                "Where the CL frame lies in the cell's base frame: x,y,z,a,b,c (mm, deg)");
  c->add_option("--base", opt->base,
                "Right-hand side of $BASE = (the offset base of a coupled table); default "
                "BASE_DATA[n] with n from the cell's <controller base-data>, else 1");
  c->add_option("--tool", opt->tool,
                "Right-hand side of $TOOL = before the first tool change (default TOOL_DATA[1])");
  c->add_option("--tools", opt->tools_path,
                "Tool table file (XML, docs/tools.md): CL tool number -> TOOL_DATA index and "
                "length; default: the cell's table, else TOOL_DATA[n] with the CL file's length");
  c->add_option("--msys", opt->msys,
                "What NX's MSYS means: ignore (the MCS is the workpiece frame; default) or apply "
                "(the CL data turned into NX's absolute frame)")
      ->check(CLI::IsMember({"ignore", "apply"}));
  c->add_option("--clearance", opt->clearance,
                "Clearance height (mm, z in the CL frame): above it a rapid may be a PTP; below "
                "it, and everywhere without it, rapids are straight LINs");
  c->add_option("--rapid-vel", opt->rapid_velocity_m_per_s,
                "$VEL.CP of rapids written as LIN, m/s (default 0.25)");
  c->add_option("--max-bytes", opt->max_bytes,
                "Largest .src in bytes: a larger program is split into parts (default: the "
                "template set's <limits>, else 512 KiB)");
  c->add_option("--apo", opt->apo_mm, "Blending distance $APO.CDIS in mm (default 0.5)");
  c->add_option("--split", opt->split, "Motions per file; 0 keeps one file (default 0)")
      ->check(non_negative_number());
  c->add_option("--cl-line-every", opt->cl_line_every,
                "A comment with the CL line every N motions (default 50, 0: never)")
      ->check(non_negative_number());
  c->add_option("--chordal-tol", opt->chordal_tolerance_mm,
                "Chordal tolerance for arcs and NURBS in mm (default 0.01)");
  c->add_option("--fit-tol", opt->fit_tolerance_mm,
                "Point reduction (docs/timing.md): consecutive cutting points merged into one LIN "
                "within this distance of each dropped point, mm (default 0.01; 0: every point "
                "kept)");
  c->add_option("--fit-ang-tol", opt->fit_angle_tolerance_deg,
                "Point reduction: the tool axis within this angle of each dropped point's, deg "
                "(default 0.1)");
  c->add_option("--plan", opt->plan,
                "Redundancy along the path (docs/redundancy.md): global plans table, track and "
                "spin over the path ahead first (default); local is Algorithm 1 pose by pose")
      ->check(CLI::IsMember({"global", "local"}));
  c->add_option("--preset", opt->preset,
                "What the global plan weighs most: smooth (little axis travel; default), stiff "
                "(the arm's conditioning), fast (no time lost to axis limits)")
      ->check(CLI::IsMember({"smooth", "stiff", "fast"}));
  c->add_option("--keyframe-spacing", opt->keyframe_spacing_mm,
                "Path between the global plan's keyframes, mm (default 20)");
  c->add_option("--threads", opt->threads,
                "Threads for the conversion: 0 one per core, at most 8 (default); 1 one thread. "
                "The file is read, the plan solved and the program tracked and written on "
                "threads of their own; the program is the same for any count")
      ->check(CLI::Range(0, 256));
  c->add_option("--lock", opt->locks,
                "Hold an external axis: E1=500 at that value (mm or deg; global plan), E2 where "
                "the first pose puts it; may be repeated");
  c->add_flag("--predict-deflection", opt->predict_deflection,
              "Predict the tool's deflection under the cutting force at every cutting move "
              "(the cell needs joint stiffness; docs/deflection.md)");
  c->add_flag("--compensate", opt->compensate,
              "Move every cutting target against the predicted deflection (implies "
              "--predict-deflection)");
  c->add_option("--cutting", opt->cutting_path,
                "Cutting conditions per operation (XML, docs/deflection.md); default: 4 teeth, "
                "ae 50 % and ap 25 % of the diameter, Al7075-T6, down-milling");
  c->add_option("--deflection-tol", opt->deflection_tolerance_mm,
                "Tolerance the deflection normal to the wall is judged against, mm (default "
                "0.05)")
      ->check(CLI::Range(1e-6, 100.0));
  c->add_option("--fixture", opt->fixtures,
                "A fixture's STL (ASCII or binary, mm, in the CL frame): no moving body may come "
                "within the margin of it; may be repeated (docs/collision.md)");
  c->add_option("--part", opt->part,
                "The finished part's STL (mm, in the CL frame): only the cutter's flute may "
                "touch it");
  c->add_option("--collision-margin", opt->collision_margin_mm,
                "Least distance kept between bodies that may not touch, mm (default 5)")
      ->check(CLI::Range(0.0, 1000.0));
  c->add_flag("--no-collision-check", opt->no_collision,
              "Check no body at all (the cell's, the tool's, the set-up's): for a cell whose "
              "bodies are not yet right; the program is then not proven clear");
  c->add_flag("-q,--quiet", opt->quiet, "No progress and no summary");
  return [opt] {
    try {
      return run_convert(*opt);
    } catch (const BadArgument& e) {
      fmt::print(stderr, "{}\n", e.message);
      return kExitBadInput;
    }
  };
}

}  // namespace redpost::cli
