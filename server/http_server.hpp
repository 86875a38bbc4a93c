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
  void serve();  // blocks until stop(); returns after every in-flight request has been answered
  // Graceful shutdown, step 1: /readyz turns 503 and new compute requests get 503 "shutting_down"; step 2:
  // the listening socket closes (no new connections). In-flight requests continue.
  void begin_drain();
  void stop();
  // Past the grace period: in-flight computations stop at their next deadline check (503 "cancelled").
  void cancel_in_flight();
  int in_flight() const;
  // Since the last connection was accepted or request began (any route): how long the service has been quiet.
  double seconds_since_activity() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wish::server
