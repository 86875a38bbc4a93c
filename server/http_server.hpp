#pragma once
// The HTTP front end (cpp-httplib): routes, request ids, auth, the access line and request metrics. httplib.h is
// included only in http_server.cpp (it must not share a translation unit with Eigen); this header is free of both.

#include <memory>

#include "server/config.hpp"
#include "server/metrics.hpp"
#include "server/model_registry.hpp"
#include "server/worker_pool.hpp"

namespace wish::server {

class HttpServer {
 public:
  HttpServer(const ServerConfig& config, ModelRegistry& models, WorkerPool& pool, Metrics& metrics);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int bind();    // binds config.host:config.port (0: any free port); returns the port; throws std::runtime_error
  // Accepts connections until begin_shutdown(), then returns once every connection accepted before it (the
  // kernel's queue included, listener.hpp) has been answered and closed.
  void serve();
  // Shutdown, step 1 (SIGTERM/SIGINT): stop accepting (later connects are refused); /readyz turns 503; every
  // request already sent on an open connection is answered in full — its body still arriving, queued or
  // computing — with Connection: close; idle kept-alive connections close.
  void begin_shutdown();
  // Step 2, past the grace period: computations are cancelled (503 "cancelled"), requests not yet computing and
  // bodies still arriving are answered 503 "shutting_down" (both with Retry-After), silent connections close.
  void end_grace();
  int in_flight() const;         // compute requests between their body and their answer
  int open_connections() const;  // accepted and not yet closed

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wish::server
