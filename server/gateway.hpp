#pragma once
// The service logic behind the routes, free of HTTP (llama.cpp tools/server's split: the transport, http_server.cpp,
// turns an httplib request into the neutral values below and writes the ApiResponse back; everything between lives
// here and is tested without a socket, tests/server/gateway_test.cpp):
//   model resolution (?model=, the default, "several loaded, none default"), admission (shutdown grace over -> 503),
//   fan-out of one job per part to the worker pool (all or none; queue full -> 503), the deadline arithmetic
//   (the time limit counts from the request's arrival, queue wait included), waiting (a job not done by the limit
//   + 1 s is cancelled and answered 504), the cancel registry, and batch assembly (one result or error per part).
// Eigen-free and httplib-free.

#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "server/api_response.hpp"
#include "server/cancel_registry.hpp"
#include "server/compute_service.hpp"
#include "server/config.hpp"
#include "server/metrics.hpp"
#include "server/model_registry.hpp"
#include "server/request_parsing.hpp"
#include "server/worker_pool.hpp"

namespace wish::server {

// A /v1/describe or /v1/classify request as the transport read it.
struct ComputeRequest {
  Operation op = Operation::Describe;
  std::string request_id;
  std::chrono::steady_clock::time_point arrival = std::chrono::steady_clock::now();
  ParamMap params;               // query parameters; a multipart body's parameter fields are merged in here
  bool multipart = false;
  std::vector<FormPart> form;    // multipart: every part as read
  std::string body;              // raw body
  std::string content_type;      // raw body: the request's Content-Type
};

// 503 "shutting_down" with Retry-After: a request the server will not compute because its shutdown grace period is
// over (the transport answers a request whose body was cut short by it the same way).
ApiError shutting_down_error();

class Gateway {
 public:
  // One job's work; run_compute (compute_service.hpp) in the service, a stand-in in tests. Must not throw.
  using ComputeFunction = std::function<ComputeOutcome(const ComputeJob&, const ServerConfig&)>;

  Gateway(const ServerConfig& config, ModelRegistry& models, WorkerPool& pool, Metrics& metrics,
          CancelRegistry& cancels, ComputeFunction compute = run_compute);

  ApiResponse health() const;                                          // GET /healthz
  ApiResponse ready(const std::string& request_id) const;              // GET /readyz
  ApiResponse metrics_text() const;                                    // GET /metrics
  ApiResponse list_models() const;                                     // GET /v1/models
  ApiResponse model(const std::string& name, const std::string& request_id) const;  // GET /v1/models/{name}
  // GET /v1/models/{name}/report: the training report beside the model file, as written (404 model_not_found,
  // 404 report_not_found when there is none or it is not a JSON object).
  ApiResponse model_report(const std::string& name, const std::string& request_id) const;
  ApiResponse reload();                                                // POST /v1/admin/reload
  // POST /v1/describe, /v1/classify. Never throws: every failure is an error response.
  ApiResponse compute(ComputeRequest request);

  // Graceful shutdown. Draining: /readyz is 503 (load balancers stop sending); compute requests still arriving
  // were sent before the listener closed and are computed. Past the grace period: compute requests are refused
  // with 503 "shutting_down" (the ones waiting are cancelled through the cancel registry).
  void begin_drain() { draining_ = true; }
  void end_grace() { grace_over_ = true; }
  bool draining() const { return draining_.load(); }
  int in_flight() const { return in_flight_.load(); }

 private:
  // The model a classify request names (or the default); nullptr for describe. Throws model_not_found (404),
  // no_model_loaded (503), model_required (400).
  std::shared_ptr<const LoadedModel> resolve_model(Operation op, const ComputeParams& params) const;
  // Queues one job per part (all or none) and waits for them up to the request's time limit.
  std::vector<ComputeOutcome> run_parts(const ComputeRequest& request, const ComputeParams& params,
                                        const std::shared_ptr<const LoadedModel>& model,
                                        const std::vector<MeshPart>& parts);
  ApiResponse assemble(const ComputeRequest& request, const std::vector<MeshPart>& parts,
                       std::vector<ComputeOutcome>& outcomes);

  const ServerConfig& config_;
  ModelRegistry& models_;
  WorkerPool& pool_;
  Metrics& metrics_;
  CancelRegistry& cancels_;
  ComputeFunction compute_;
  std::atomic<bool> draining_{false};
  std::atomic<bool> grace_over_{false};
  std::atomic<int> in_flight_{0};
};

}  // namespace wish::server
