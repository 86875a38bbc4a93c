#pragma once
// The bridge between the HTTP front end and core: one job = one mesh through the pipeline, run on a worker.
// Eigen-free interface (http_server.cpp includes it); compute_service.cpp is where core's Eigen types live.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "core/common/deadline.hpp"
#include "server/config.hpp"
#include "server/error_mapping.hpp"
#include "server/model_registry.hpp"
#include "server/request_parsing.hpp"

namespace wish::server {

struct ComputeJob {
  Operation op = Operation::Describe;
  ComputeParams params;
  std::shared_ptr<const LoadedModel> model;  // classify: the model this request started with
  MeshPart part;
  std::string request_id;                     // echoed in each object result of a label volume
  Deadline deadline;                          // from request arrival; queue wait counts
  std::chrono::steady_clock::time_point submitted{};
};

struct ComputeOutcome {
  // A mesh: 200 with its result, or its error. A label volume: its objects' status (200, their common refusal
  // status, or 207 when they differ: api_response.hpp batch_status) with its VolumeResult either way.
  int status = 500;
  nlohmann::json result;                 // DescribeResult / VolumeResult without request_id; null when failed whole
  ApiError error;                        // status != 200 (a volume: its first refused object's)
  std::map<std::string, double> stages;  // seconds: queue_wait, read, validate, map, fit, classify, total
  std::int64_t vertices = -1, faces = -1;  // of the mesh as read, when it got that far
};

// Never throws: every failure becomes an outcome through error_mapping.
ComputeOutcome run_compute(const ComputeJob& job, const ServerConfig& config) noexcept;

// classify.md's rule: explicit descriptor parameters that differ from the model's are refused (400
// "descriptor_mismatch", naming both values) rather than silently computing a descriptor the model was not trained
// on; absent parameters mean "use the model's". Throws InvalidInputError.
void check_descriptor_settings(const ComputeParams& params, const LoadedModel& model);

}  // namespace wish::server
