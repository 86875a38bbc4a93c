// `wish`: one executable, one subcommand per stage of the method (inspect, map, describe, reconstruct,
// train, predict, serve). Subcommands live in cli/cmd_*.cpp and register themselves.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <initializer_list>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/command_registry.hpp"
#include "core/common/errors.hpp"
#include "core/common/process_heap.hpp"
#include "core/common/process_signals.hpp"
#include "core/common/stage_profile.hpp"
#include "core/common/thread_policy.hpp"

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

// One BLAS thread unless the user chose a count (the variables OpenBLAS reads, in its order). With OpenBLAS's
// default (one thread per core) a nucleus map's Dirac factorisations ran partly on a second thread: 9 % more CPU
// for the process and no shorter wall time on 2 cores (whole-process pairs, docs/benchmarks.md #28). The service's
// workers and training run on one BLAS thread already (core/common/thread_policy.hpp), so a mesh is mapped the same
// way by `wish map` as by the service: the flow's CPU budget counts the calling thread only, and a second BLAS
// thread would let a budget-bound flow do more steps.
static void default_to_one_blas_thread() {
  for (const char* name : {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
    if (std::getenv(name)) return;
  (void)wish::set_blas_thread_count(1);
  wish::stop_blas_threads();  // after: setting a count restarts a stopped OpenBLAS thread server
}

}  // namespace wish::cli

int main(int argc, char** argv) {
  using namespace wish::cli;
  (void)wish::tune_process_heap();  // before the work allocates: huge pages, memory reused (process_heap.hpp)
  default_to_one_blas_thread();
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
