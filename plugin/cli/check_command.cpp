// `redpost check`: a static check of KRL programs (docs/krl-diff.md). One line per finding,
// "file:line: message". Exit 0: no findings, 1: findings, 2: error.
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
};

int run_check(const CheckOptions& opt) {
  std::optional<Cell> cell;
  KrlCheckOptions options;
  options.max_bytes = opt.max_bytes;
  if (!opt.cell_path.empty()) {
    cell = load_cell(opt.cell_path);
    options.cell = &*cell;
  }
  const std::vector<KrlFinding> findings = check_krl(opt.path, options);
  std::string out;
  for (const KrlFinding& f : findings)
    out += fmt::format("{}:{}: {}\n", f.file, f.line, f.message);
  std::fwrite(out.data(), 1, out.size(), stdout);
  return findings.empty() ? kExitOk : kExitDifferent;
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
  return [opt] { return run_check(*opt); };
}

}  // namespace redpost::cli
