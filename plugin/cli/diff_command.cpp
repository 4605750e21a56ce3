// `redpost diff`: compares two KRL programs (or directories of them) motion by motion
// (docs/krl-diff.md). Exit 0: equal within tolerance, 1: different, 2: error.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "redpost/io/error.hpp"
#include "redpost/krl/diff.hpp"

namespace redpost::cli {

namespace {

struct DiffOptions {
  std::string a, b;
  KrlDiffOptions diff;
  bool json = false;
};

int run_diff(const DiffOptions& opt) {
  const KrlDiffResult r = diff_krl_paths(opt.a, opt.b, opt.diff);
  const std::string out =
      opt.json ? format_krl_diff_json(r, opt.diff) : format_krl_diff_text(r, opt.diff);
  std::fwrite(out.data(), 1, out.size(), stdout);
  return r.equal ? kExitOk : kExitDifferent;
}

}  // namespace

Runner add_diff_command(CLI::App& app) {
  auto opt = std::make_shared<DiffOptions>();
  CLI::App* cmd = app.add_subcommand(
      "diff",
      "Compare two KRL programs (.src, or directories of them) motion by motion: position, "
      "orientation, axes, S/T, keyword, $VEL.CP, $APO.CDIS, PTP velocity, $TOOL and $BASE, and "
      "the paths as curves. Exit 0 equal within tolerance, 1 different, 2 error.");
  cmd->add_option("A", opt->a, "First program (.src) or directory")->required();
  cmd->add_option("B", opt->b, "Second program (.src) or directory")->required();
  cmd->add_option("--pos-tol", opt->diff.pos_tol_mm, "Position tolerance (mm)")
      ->capture_default_str()
      ->check(non_negative_number());
  cmd->add_option("--ang-tol", opt->diff.ang_tol_deg, "Orientation tolerance (deg)")
      ->capture_default_str()
      ->check(non_negative_number());
  cmd->add_option("--axis-tol", opt->diff.axis_tol, "Axis tolerance, A1..A6 and E1..E6 (deg or mm)")
      ->capture_default_str()
      ->check(non_negative_number());
  cmd->add_option("--vel-tol", opt->diff.vel_tol_m_per_s, "$VEL.CP tolerance (m/s)")
      ->capture_default_str()
      ->check(non_negative_number());
  cmd->add_option("--path-tol", opt->diff.path_tol_mm,
                  "Paths as curves: largest distance from a point of one program to the other's "
                  "path (mm)")
      ->capture_default_str()
      ->check(non_negative_number());
  cmd->add_flag("--as-curves", opt->diff.as_curves,
                "Compare Cartesian positions and orientations as curves (within --path-tol and "
                "--ang-tol), not point by point: the same path with other points is equal");
  cmd->add_option("--max-shown", opt->diff.max_shown, "Differences listed")->capture_default_str();
  cmd->add_option("--window", opt->diff.window,
                  "Motions of each program held at once: how far the alignment looks ahead, and "
                  "the stretch of the other program's path each point is measured against "
                  "(memory about 0.6 KB a motion)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{16}, std::size_t{100000000}));
  cmd->add_flag("--json", opt->json, "Machine-readable report");
  return [opt] { return run_diff(*opt); };
}

}  // namespace redpost::cli
