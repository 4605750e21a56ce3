// redpost: the command-line host.
#include <signal.h>

#include <csignal>
#include <cstdio>
#include <exception>
#include <string>

#include <fmt/format.h>

#include "commands.hpp"
#include "redpost.h"
#include "redpost/io/error.hpp"

namespace {

// A stop request (kill, Ctrl-C, a closed terminal) removes the temporaries and the program lock
// before the process ends as the signal says; the default action then runs, so the parent
// still sees the signal. Only the command installs this: the library leaves signals to its host.
extern "C" void remove_temporaries_and_stop(int signal_number) {
  rp_remove_temporaries();
  std::raise(signal_number);  // SA_RESETHAND: the default action, once this handler returns
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_stop;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int s : {SIGTERM, SIGINT, SIGHUP})
    ::sigaction(s, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) must fail a write with EFBIG, as a full disk fails it with
  // ENOSPC, so that the error is reported and the temporary files are removed, instead of
  // killing the process. Only the command does this: the library leaves signals to its host.
  std::signal(SIGXFSZ, SIG_IGN);
  install_stop_handlers();
  CLI::App app{"redpost: postprocessor for redundant robotic milling cells"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("redpost ") + rp_version());

  const redpost::cli::Runner fk = redpost::cli::add_fk_command(app);
  const redpost::cli::Runner convert = redpost::cli::add_convert_command(app);
  const redpost::cli::Runner diff = redpost::cli::add_diff_command(app);
  const redpost::cli::Runner check = redpost::cli::add_check_command(app);
  const redpost::cli::Runner calibrate = redpost::cli::add_calibrate_command(app);
  const redpost::cli::Runner place = redpost::cli::add_place_command(app);

  // A first word that is no option and no subcommand: CLI11 would say "A subcommand is
  // required", as if none had been given.
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      fmt::print(stderr,
                 "redpost: unknown subcommand '{}'; the subcommands are {} (redpost --help)\n",
                 argv[1], names);
      return redpost::cli::kExitBadInput;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : redpost::cli::kExitBadInput;
  }
  try {
    if (app.got_subcommand("fk"))
      return fk();
    if (app.got_subcommand("convert"))
      return convert();
    if (app.got_subcommand("diff"))
      return diff();
    if (app.got_subcommand("check"))
      return check();
    if (app.got_subcommand("calibrate"))
      return calibrate();
    if (app.got_subcommand("place"))
      return place();
  } catch (const redpost::Error& e) {
    fmt::print(stderr, "redpost: {}\n", e.what());
    return redpost::cli::kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "redpost: internal error: {}\n", e.what());
    return 3;
  }
  return redpost::cli::kExitBadInput;
}
