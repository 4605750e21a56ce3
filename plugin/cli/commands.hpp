// Subcommands of the redpost command-line host. Each registers its options on the CLI11 app and
// returns the process exit code when run: 0 success, 2 bad input or an unreachable path.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace redpost::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitDifferent = 1;  // diff: different; check: findings
inline constexpr int kExitBadInput = 2;

using Runner = std::function<int()>;

// A number of at least 0, said so in the option's words: CLI11's own NonNegativeNumber prints
// its range with the largest double written out in 300 digits.
inline CLI::Validator non_negative_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v) || !(v >= 0.0))
          return "must be a number of at least 0, got '" + text + "'";
        return {};
      },
      "NONNEGATIVE");
}

Runner add_fk_command(CLI::App& app);
Runner add_convert_command(CLI::App& app);
Runner add_diff_command(CLI::App& app);
Runner add_check_command(CLI::App& app);
Runner add_calibrate_command(CLI::App& app);
Runner add_place_command(CLI::App& app);

}  // namespace redpost::cli
