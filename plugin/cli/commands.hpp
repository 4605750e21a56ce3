// Subcommands of the redpost command-line host. Each registers its options on the CLI11 app and
// returns the process exit code when run: 0 success, 2 bad input or an unreachable path.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace redpost::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitDifferent = 1;  // diff: different; check: findings
inline constexpr int kExitBadInput = 2;

using Runner = std::function<int()>;

Runner add_fk_command(CLI::App& app);
Runner add_convert_command(CLI::App& app);
Runner add_diff_command(CLI::App& app);
Runner add_check_command(CLI::App& app);
Runner add_calibrate_command(CLI::App& app);
Runner add_place_command(CLI::App& app);

}  // namespace redpost::cli
