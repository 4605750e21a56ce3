// `redpost check`: a static check of KRL programs (docs/krl-diff.md). One line per finding,
// "file:line: message" ("file:line: warning: message" for what the controller runs, but not as
// written: the motion rate, docs/timing.md). Exit 0: no findings (warnings aside unless
// --strict), 1: findings, 2: error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "commands.hpp"
#include "redpost/collision/setup.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/krl/check.hpp"

namespace redpost::cli {

namespace {

struct CheckOptions {
  std::string path;
  std::string cell_path;
  size_t max_bytes = kKrlDefaultMaxBytes;
  size_t program_memory = 0;
  double ipo_cycle_ms = 12.0;
  double orientation_deg_s = 200.0;
  bool strict = false;
  // The clearance (docs/collision.md): the set-up, where the CL frame lies, the tools, the margin.
  std::vector<std::string> fixtures;
  std::string part;
  std::string placement;
  std::string tools_path;
  double margin_mm = 5.0;
  bool clearance = false;  // --clearance: the cell's own bodies without a set-up
  std::string base;        // --base: the frame E6POS targets are in, in {B}
};

// "x,y,z,a,b,c" (mm, deg) -> a frame in {B}; refused with the option's name.
Isometry placement_frame(const std::string& text, const char* option = "--placement") {
  double v[6];
  int n = 0;
  std::size_t i = 0;
  while (n < 7) {
    const std::size_t j = text.find(',', i);
    const std::string token = text.substr(i, j == std::string::npos ? std::string::npos : j - i);
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0' || !std::isfinite(x) || n == 6)
      throw Error(
          ErrorCode::bad_input,
          std::string(option) + " takes six numbers x,y,z,a,b,c (mm and deg), got '" + text + "'");
    v[n++] = x;
    if (j == std::string::npos)
      break;
    i = j + 1;
  }
  if (n != 6)
    throw Error(
        ErrorCode::bad_input,
        std::string(option) + " takes six numbers x,y,z,a,b,c (mm and deg), got '" + text + "'");
  return frame_from_xyzabc(v[0], v[1], v[2], KukaAbc{v[3], v[4], v[5]});
}

int run_check(const CheckOptions& opt) {
  std::optional<Cell> cell;
  KrlCheckOptions options;
  options.max_bytes = opt.max_bytes;
  options.max_program_bytes = opt.program_memory;
  std::optional<KrlClearanceOptions> clearance;
  std::vector<std::pair<std::string, KrlClearanceTotals>> totals;
  if (!opt.cell_path.empty()) {
    cell = load_cell(opt.cell_path);
    options.cell = &*cell;
    if (opt.clearance || !opt.fixtures.empty() || !opt.part.empty()) {
      clearance.emplace();
      clearance->cell = &*cell;
      clearance->cell_bodies = load_cell_bodies(*cell);
      const Isometry T_B_part =
          opt.placement.empty() ? Isometry::Identity() : placement_frame(opt.placement);
      clearance->setup = setup_bodies(SetupFiles{opt.fixtures, opt.part}, T_B_part);
      clearance->tools = opt.tools_path.empty() ? cell->tools : load_tool_table(opt.tools_path);
      clearance->margin_mm = opt.margin_mm;
      if (!opt.base.empty())
        clearance->T_B_base = placement_frame(opt.base, "--base");
      options.clearance = &*clearance;
      options.clearance_totals = &totals;
    }
  } else if (!opt.fixtures.empty() || !opt.part.empty() || opt.clearance) {
    throw Error(ErrorCode::bad_input,
                "--clearance, --fixture and --part need --cell: the clearance is computed with "
                "the cell's kinematics");
  }
  options.motion_rate.interpolation_cycle_s = opt.ipo_cycle_ms / 1000.0;
  options.motion_rate.orientation_velocity_deg_s = opt.orientation_deg_s;
  std::vector<std::pair<std::string, KrlMotionRate>> rates;
  options.motion_rates = &rates;
  const std::vector<KrlFinding> findings = check_krl(opt.path, options);
  std::string out;
  bool failed = false;
  for (const KrlFinding& f : findings) {
    out += fmt::format("{}:{}: {}{}\n", f.file, f.line, f.warning ? "warning: " : "", f.message);
    failed = failed || !f.warning || opt.strict;
  }
  // The motion rate of each program, where some motion is shorter than a cycle.
  for (const auto& [file, r] : rates) {
    if (r.below_cycle == 0)
      continue;
    out += fmt::format(
        "{}: motion rate: {} of {} CP motions ({:.1f} %) last less than one {:g} ms "
        "interpolation cycle at their $VEL.CP; the shortest {:.1f} ms at {}:{}{}\n",
        file, r.below_cycle, r.cp_motions,
        100.0 * static_cast<double>(r.below_cycle) / static_cast<double>(r.cp_motions),
        opt.ipo_cycle_ms, 1000.0 * r.shortest_s, r.shortest_file, r.shortest_line,
        r.spline_joined > 0 ? fmt::format(" ({} SPLINE segments joined smoothly not counted: "
                                          "one path to the controller)",
                                          r.spline_joined)
                            : std::string());
  }
  // The clearance of each program (docs/collision.md).
  for (const auto& [file, t] : totals) {
    if (!t.checked) {
      out += fmt::format(
          "{}: clearance: no bodies to check (the cell has no <collision>, no "
          "tool geometry, no --fixture or --part)\n",
          file);
      continue;
    }
    const std::string closest = t.least_mm <= 0.0 ? std::string("touching or overlapping")
                                                  : fmt::format("{:.1f} mm", t.least_mm);
    out += std::isfinite(t.least_mm)
               ? fmt::format("{}: clearance: {} motions checked; closest {} ({}) at {}:{}\n", file,
                             t.motions, closest, t.least_pair, t.least_file, t.least_line)
               : fmt::format("{}: clearance: {} motions checked; no two bodies within {:g} mm\n",
                             file, t.motions, opt.margin_mm + 25.0);
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return failed ? kExitDifferent : kExitOk;
}

}  // namespace

Runner add_check_command(CLI::App& app) {
  auto opt = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check",
      "Static check of a KRL program (.src) or of every program in a directory. Prints "
      "'file:line: message' per finding. Exit 0 clean, 1 findings, 2 error.");
  cmd->add_option("PATH", opt->path, "Program (.src) or directory")->required();
  cmd->add_option("--cell", opt->cell_path,
                  "Cell definition (XML): check A1..A6/E1..E6 against its joint limits");
  cmd->add_option("--max-bytes", opt->max_bytes, "Largest file size accepted (bytes)")
      ->capture_default_str();
  cmd->add_option("--program-memory", opt->program_memory,
                  "The controller's program memory (bytes): a program whose files together take "
                  "more cannot be loaded at once; 0: not checked")
      ->capture_default_str();
  cmd->add_option("--ipo-cycle", opt->ipo_cycle_ms,
                  "The controller's interpolation cycle (ms): CP motions shorter than one at "
                  "their $VEL.CP are warned about; 0: not checked")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--orientation-velocity", opt->orientation_deg_s,
                  "$VEL.ORI1 (deg/s) for the time of a motion that turns")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 10000.0));
  cmd->add_flag("--strict", opt->strict, "Warnings (the motion rate) fail the check too");
  cmd->add_option("--fixture", opt->fixtures,
                  "With --cell: a fixture's STL (mm, in the CL frame); the clearance of every "
                  "motion is recomputed from the program's text; may be repeated");
  cmd->add_option("--part", opt->part,
                  "With --cell: the finished part's STL (mm, in the CL frame); only the cutter "
                  "may touch it");
  cmd->add_option("--placement", opt->placement,
                  "Where the CL frame (and so the set-up's STL) lies in the cell's base frame: "
                  "x,y,z,a,b,c (mm, deg), as given to convert");
  cmd->add_option("--tools", opt->tools_path,
                  "Tool table (XML): each $TOOL's length and geometry; default the cell's");
  cmd->add_option("--collision-margin", opt->margin_mm,
                  "Least distance between bodies that may not touch, mm (default 5)")
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_flag("--clearance", opt->clearance,
                "With --cell: recompute the clearance of the cell's and the tools' bodies even "
                "without --fixture or --part");
  cmd->add_option("--base", opt->base,
                  "The frame the program's E6POS targets are in ($BASE), in the cell's base "
                  "frame: x,y,z,a,b,c (mm, deg); default the cell's base frame, as convert writes");
  return [opt] { return run_check(*opt); };
}

}  // namespace redpost::cli
