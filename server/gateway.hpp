#pragma once
// The service logic behind the routes, free of HTTP (llama.cpp tools/server's split: the transport, http_server.cpp,
// turns an httplib request into the neutral values below and writes the ApiResponse back; everything between lives
// here and is tested without a socket, tests/server/gateway_test.cpp):
//   model resolution (?model=, the default, "several loaded, none default"), admission from the request's headers
//   before its body is read (shutdown grace over, Content-Length past the upload limit, a full queue, or a predicted
//   finish past the time limit: refused at once), fan-out of one job per part to the worker pool (all or none; the
//   first part takes the place held since admission; no place for the rest -> 503), the deadline arithmetic
//   (the time limit counts from the request's arrival, queue wait included), waiting (a job not done by the limit
//   + 1 s is cancelled and answered 504), the cancel registry, and batch assembly (one result or error per part).
// Eigen-free and httplib-free.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/api_response.hpp"
#include "server/cancel_registry.hpp"
#include "server/compute_service.hpp"
#include "server/config.hpp"
#include "server/metrics.hpp"
#include "server/model_registry.hpp"
#include "server/request_parsing.hpp"
#include "server/work_backlog.hpp"
#include "server/worker_pool.hpp"

namespace wish::server {

// A compute request's place from its admission (its headers) until its jobs are queued: a place in the worker
// queue and its predicted seconds in the work backlog. Dropped unused (the body could not be read): both freed.
struct Admission {
  WorkerPool::Reservation place;
  std::shared_ptr<WorkBacklog::Ticket> ticket;
};

// What the transport knows of a compute request before reading its body.
struct AdmissionQuery {
  std::chrono::steady_clock::time_point arrival = std::chrono::steady_clock::now();
  std::optional<std::uint64_t> content_length;  // none: a chunked body (its size is capped while it is read)
};

struct AdmissionVerdict {
  std::shared_ptr<Admission> admission;  // admitted
  ApiResponse refusal;                   // otherwise: the answer to send without reading the body
  bool admitted() const { return admission != nullptr; }
};

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
  std::shared_ptr<Admission> admission;  // from Gateway::admit before the body was read; none: compute() admits it
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
  // Admission of a POST /v1/describe or /v1/classify from its headers, before its body is read (the transport then
  // answers a refusal without reading the body). Refused: 503 shutting_down past the grace period; 413
  // payload_too_large for a Content-Length past the upload limit; 503 queue_full with Retry-After when the queue
  // holds queue_size jobs, or when the predicted wait for a worker plus the request's own predicted seconds pass
  // admit_fraction of its time limit (work_backlog.hpp; never when a worker would be free at once).
  AdmissionVerdict admit(const AdmissionQuery& query, const std::string& request_id);
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
  // admit() without the answer: the admission, or null with `refusal` set.
  std::shared_ptr<Admission> take_place(const AdmissionQuery& query, ApiError& refusal);
  // Queues one job per part (all or none; the first takes the admission's place) and waits for them up to the
  // request's time limit.
  std::vector<ComputeOutcome> run_parts(const ComputeRequest& request, const ComputeParams& params,
                                        const std::shared_ptr<const LoadedModel>& model,
                                        const std::vector<MeshPart>& parts, Admission& admission);
  ApiResponse assemble(const ComputeRequest& request, const std::vector<MeshPart>& parts,
                       std::vector<ComputeOutcome>& outcomes);

  const ServerConfig& config_;
  ModelRegistry& models_;
  WorkerPool& pool_;
  Metrics& metrics_;
  CancelRegistry& cancels_;
  ComputeFunction compute_;
  std::shared_ptr<WorkBacklog> backlog_;
  std::atomic<bool> draining_{false};
  std::atomic<bool> grace_over_{false};
  std::atomic<int> in_flight_{0};
};

}  // namespace wish::server
