// `redpost check`: a static check of KRL programs (docs/krl-diff.md). One line per finding,
// "file:line: message" ("file:line: warning: message" for what the controller runs, but not as
// written: the motion rate, docs/timing.md). Exit 0: no findings (warnings aside unless
// --strict), 1: findings, 2: error.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "commands.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
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
};

int run_check(const CheckOptions& opt) {
  std::optional<Cell> cell;
  KrlCheckOptions options;
  options.max_bytes = opt.max_bytes;
  options.max_program_bytes = opt.program_memory;
  if (!opt.cell_path.empty()) {
    cell = load_cell(opt.cell_path);
    options.cell = &*cell;
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
  return [opt] { return run_check(*opt); };
}

}  // namespace redpost::cli
