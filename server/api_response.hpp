#pragma once
// The neutral response value the gateway (gateway.hpp) returns and the HTTP transport (http_server.cpp) writes to
// the wire: a status, headers, a body and what the access line reports. No httplib, no Eigen.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/error_mapping.hpp"

namespace wish::server {

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // besides Content-Type

  // For the access line and metrics (logging.hpp), not sent.
  std::string error_code;                    // the first error code of the response ("" when none)
  int parts = 0;                             // mesh / volume parts in a compute request
  std::int64_t vertices = -1, faces = -1;    // summed over the parts that were read

  const std::string* header(const std::string& name) const;  // nullptr when absent
};

// A JSON body; non-UTF-8 strings are replaced rather than thrown on.
ApiResponse json_response(int status, const nlohmann::json& body);
// The one error body (error_mapping.hpp) with Retry-After (503) and WWW-Authenticate (401) headers.
ApiResponse error_response(const ApiError& error, const std::string& request_id);

// The status of an answer made of items with their own statuses (RFC 4918 §13 Multi-Status): the parts of a
// multipart (batch) request, the objects of a label volume. The items' common status when they all agree (all
// 200 -> 200, every item 422 -> 422, so `curl -f` sees a single bad upload fail), 207 when they differ. The body
// is the same BatchResponse / VolumeResult either way.
int batch_status(const std::vector<int>& part_statuses);

}  // namespace wish::server
