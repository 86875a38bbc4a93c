#include "server/run_server.hpp"

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include <spdlog/spdlog.h>

#include "core/linalg/blas_info.hpp"
#include "server/error_mapping.hpp"
#include "server/http_server.hpp"
#include "server/logging.hpp"
#include "server/metrics.hpp"
#include "server/model_registry.hpp"
#include "server/signals.hpp"
#include "server/worker_pool.hpp"

namespace wish::server {

int run_server(ServerConfig config) {
  SignalWatcher::block_signals();  // before any thread: every thread inherits the mask (signals.hpp)
  config.finalize();
  configure_logging(config.json_log, config.log_level);
  set_retry_after_seconds(config.retry_after_seconds);

  spdlog::info("wish serve: effective configuration (flags > WISH_* environment > defaults):");
  std::istringstream lines(config.describe());
  for (std::string line; std::getline(lines, line);) spdlog::info("  {}", line);
  spdlog::info("BLAS: {}; compute workers use 1 OpenMP and 1 BLAS thread each", wish::linalg::describe_blas());

  if (!config.web_dir.empty() && !std::filesystem::is_regular_file(config.web_dir / "index.html"))
    spdlog::warn("web page: no index.html in {} (the page is web/src of the source tree); GET / is 404",
                 config.web_dir.string());
  if (!config.web_dir.empty() && !std::filesystem::is_regular_file(config.three_dir / "build" / "three.module.js"))
    spdlog::warn("web page: no three.js in '{}' (Debian's libjs-three: scripts/install-deps.sh installs it); the "
                 "page's 3-D views will not load", config.three_dir.string());

  ModelRegistry models(config.models_dir, config.default_model);
  models.reload();
  if (models.size() == 0) spdlog::warn("no model loaded: /readyz is 503 and /v1/classify refuses until a reload");

  Metrics metrics;
  WorkerPool pool(config.workers, config.queue_size);
  HttpServer http(config, models, pool, metrics);
  const int port = http.bind();
  spdlog::info("listening on http://{}:{}", config.host, port);

  // Shutdown (SIGTERM/SIGINT): every request the server accepted is answered. The listener stops accepting at once,
  // after taking the connections the kernel had already completed (closing it with them queued resets them: seen
  // as curl's 000 for 4 of 8 classify requests). Then every request already sent — its body still arriving, queued
  // or computing — gets its full answer; idle kept-alive connections close (http_server.hpp). Past the grace period
  // what is left is cancelled and answered 503 with Retry-After, so the process exits in bounded time.
  std::mutex mutex;
  std::condition_variable cv;
  bool served = false, terminating = false;
  std::thread stopper;
  {
    SignalWatcher signals(
        [&] { metrics.count_reload(models.reload().ok()); },
        [&](int sig) {
          spdlog::info("signal {}: draining ({} request(s) in flight, {} connection(s) open, grace {} s)", sig,
                       http.in_flight(), http.open_connections(), config.shutdown_grace_seconds);
          http.begin_shutdown();
          std::lock_guard lock(mutex);
          terminating = true;
          cv.notify_all();
        });
    stopper = std::thread([&] {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return terminating || served; });
      const auto grace_end = std::chrono::steady_clock::now() +
                             std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(config.shutdown_grace_seconds));
      if (cv.wait_until(lock, grace_end, [&] { return served; })) return;
      spdlog::warn("grace period over: {} connection(s) open, {} request(s) computing: cancelled, answered 503",
                   http.open_connections(), http.in_flight());
      http.end_grace();
    });
    http.serve();  // returns once the listener is closed and every connection it took is answered and closed
    {
      std::lock_guard lock(mutex);
      served = true;
      cv.notify_all();
    }
    stopper.join();
  }
  pool.shutdown();
  spdlog::info("stopped");
  return 0;
}

}  // namespace wish::server
