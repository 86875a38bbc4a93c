// `wish serve [--models DIR] --port 8080 ...`: runs the HTTP service. The service is its own executable,
// `wish-server` (server/bin/main.cpp, built next to `wish`), so `wish` links no HTTP code; this command replaces the
// process with it (exec: same pid, same blocked signals, same environment — a container's PID 1 stays the server).
// Every argument after `serve` goes to it unchanged; `wish serve --help` lists the service's options.
// WISH_SERVER_BIN overrides where the service executable is looked up.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/command_registry.hpp"

namespace wish::cli::serve_command {  // one namespace per command: the commands compile in one unity batch
namespace {

std::filesystem::path server_executable() {
  if (const char* env = std::getenv("WISH_SERVER_BIN"); env && *env) return env;
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (ec ? std::filesystem::path("wish") : self).parent_path() / "wish-server";
}

CommandRunner setup_serve(CLI::App& sub) {
  // Nothing is parsed here: the service owns its options (and --help), so they are documented in one place.
  sub.set_help_flag();
  sub.allow_extras();
  sub.prefix_command();
  return [&sub] {
    const std::filesystem::path exe = server_executable();
    std::vector<std::string> args{exe.string()};
    for (const auto& a : sub.remaining()) args.push_back(a);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(exe.c_str(), argv.data());
    std::cerr << "wish serve: cannot run the service executable " << exe << ": " << std::strerror(errno)
              << " (it is built next to `wish` as wish-server; WISH_SERVER_BIN names another)\n";
    return kExitError;
  };
}

const bool registered = register_command(
    {"serve", "Run the HTTP service (classify / describe over REST) on a worker pool; `wish serve --help` for options",
     &setup_serve, 70, /*takes_signals=*/true});

}  // namespace
}  // namespace wish::cli::serve_command
