// `wish`: one executable, one subcommand per stage of the method (inspect, map, describe, reconstruct,
// train, predict, serve). Subcommands live in cli/cmd_*.cpp and register themselves.
#include <algorithm>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/command_registry.hpp"
#include "core/common/errors.hpp"
#include "core/common/process_heap.hpp"
#include "core/common/process_signals.hpp"
#include "core/common/stage_profile.hpp"

namespace wish::cli {

static std::vector<Command>& registry() {
  static std::vector<Command> commands;
  return commands;
}

bool register_command(Command command) {
  registry().push_back(std::move(command));
  return true;
}

const std::vector<Command>& registered_commands() { return registry(); }

}  // namespace wish::cli

int main(int argc, char** argv) {
  using namespace wish::cli;
  (void)wish::tune_process_heap();  // before the work allocates: huge pages, memory reused (process_heap.hpp)
  wish::profile::enable_stage_profile_from_environment();
  // The table goes to stderr whatever path main() leaves by (a failed map returns early).
  struct PrintProfile {
    ~PrintProfile() {
      if (wish::profile::stage_profile_enabled()) std::cerr << wish::profile::stage_profile_table();
    }
  } print_profile;
  CLI::App app{"WISH: rotation-invariant spectral shape descriptors and cell-type classification of "
               "closed genus-0 meshes (Willmore flow + spherical harmonics + SVM)"};
  app.set_version_flag("--version", std::string("wish ") + WISH_VERSION);
  app.require_subcommand(1);

  auto commands = registered_commands();
  std::stable_sort(commands.begin(), commands.end(), [](const Command& a, const Command& b) { return a.order < b.order; });
  struct Runner {
    CLI::App* sub;
    CommandRunner run;
    bool takes_signals;
  };
  std::vector<Runner> runners;
  for (const auto& command : commands) {
    CLI::App* sub = app.add_subcommand(command.name, command.description);
    runners.push_back({sub, command.setup(*sub), command.takes_signals});
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  try {
    for (auto& [sub, run, takes_signals] : runners) {
      if (!sub->parsed()) continue;
      if (!takes_signals) wish::unblock_process_signals();
      return run();
    }
  } catch (const wish::WishError& e) {
    std::cerr << "wish: error [" << e.code() << "]: " << e.what() << "\n";
    return kExitInvalid;
  } catch (const std::exception& e) {
    std::cerr << "wish: unexpected error: " << e.what() << "\n";
    return kExitError;
  }
  return kExitUsage;
}
