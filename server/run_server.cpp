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
    spdlog::warn("web page: no index.html in {} (build it: cmake --build ... --target wish_web); GET / is 404",
                 config.web_dir.string());

  ModelRegistry models(config.models_dir, config.default_model);
  models.reload();
  if (models.size() == 0) spdlog::warn("no model loaded: /readyz is 503 and /v1/classify refuses until a reload");

  Metrics metrics;
  WorkerPool pool(config.workers, config.queue_size);
  HttpServer http(config, models, pool, metrics);
  const int port = http.bind();
  spdlog::info("listening on http://{}:{}", config.host, port);

  // Shutdown (SIGTERM/SIGINT) in two phases. Drain: the listener stays open, new requests get 503 shutting_down
  // (load balancers and clients retry elsewhere) and /readyz turns 503, while the requests already computing finish.
  // Then stop: the listener closes. Closing it at once would lose requests: httplib closes a connection it accepted
  // but had not started to read once it is stopping, and the kernel resets those still in the accept backlog
  // (seen as RemoteDisconnected / ECONNRESET by clients under load, tests/server/test_server_signals.py).
  // Nor is "nothing in flight" enough: a client answered a moment ago sends its next request at once, and a request
  // still being sent is not in flight yet; so the stop also waits for a quiet moment (no connection accepted, no
  // request begun, for kQuietSeconds), in which such requests are answered 503 shutting_down instead of reset. A
  // load balancer that saw /readyz turn 503 sends nothing more, so it costs half a second. Seen without it: two
  // classify requests reset, sent the moment their clients' previous answers came, while the stop closed the
  // listener (one run of test_server_signals.py's during-load loop, RUNS raised to 15, on a loaded 2-core machine).
  // Past the grace period, what still runs is cancelled, so the process exits in bounded time.
  constexpr double kQuietSeconds = 0.5;
  std::mutex mutex;
  std::condition_variable cv;
  bool served = false, terminating = false;
  std::thread stopper;
  {
    SignalWatcher signals(
        [&] { metrics.count_reload(models.reload().ok()); },
        [&](int sig) {
          spdlog::info("signal {}: draining ({} request(s) in flight, grace {} s)", sig, http.in_flight(),
                       config.shutdown_grace_seconds);
          http.begin_drain();
          std::lock_guard lock(mutex);
          terminating = true;
          cv.notify_all();
        });
    stopper = std::thread([&] {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return terminating || served; });
      if (served) return;
      const auto grace_end = std::chrono::steady_clock::now() +
                             std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(config.shutdown_grace_seconds));
      // Poll the in-flight count and the quiet time (the handlers do not signal this condition variable).
      while ((http.in_flight() > 0 || http.seconds_since_activity() < kQuietSeconds) &&
             std::chrono::steady_clock::now() < grace_end)
        cv.wait_for(lock, std::chrono::milliseconds(20));
      if (http.in_flight() > 0) {
        spdlog::warn("grace period over: cancelling {} in-flight request(s)", http.in_flight());
        http.cancel_in_flight();
      }
      http.stop();
    });
    http.serve();  // returns once stopped and every in-flight request is answered
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
