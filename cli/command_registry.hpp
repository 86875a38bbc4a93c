#pragma once
// Subcommands of `wish` register themselves at static-initialisation time, so each lives in its own
// cli/cmd_<name>.cpp:
//   static const bool registered = wish::cli::register_command({"inspect", "Report ...", &setup_inspect});
// `setup` adds the subcommand's options to the CLI::App it is given and returns the function that runs it
// (returning the process exit status).

#include <functional>
#include <string>
#include <vector>

namespace CLI { class App; }

namespace wish::cli {

using CommandRunner = std::function<int()>;

struct Command {
  std::string name;
  std::string description;
  CommandRunner (*setup)(CLI::App& sub);
  int order = 100;  // position in --help
  // true: the command takes SIGHUP / SIGTERM / SIGINT itself with sigwait and keeps them blocked in every thread
  // (core/common/process_signals.hpp); false: they are unblocked before it runs (default actions).
  bool takes_signals = false;
};

bool register_command(Command command);
const std::vector<Command>& registered_commands();

// Exit codes shared by all subcommands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInvalid = 1;   // an input was refused (invalid mesh, failed map, bad model)
inline constexpr int kExitUsage = 2;     // bad command line
inline constexpr int kExitError = 3;     // unexpected failure

}  // namespace wish::cli
