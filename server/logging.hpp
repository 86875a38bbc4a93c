#pragma once
// Log setup (spdlog to stderr, plain text or one JSON object per line) and the one access line per request.

#include <cstdint>
#include <string>

namespace wish::server {

void configure_logging(bool json, const std::string& level);

struct AccessRecord {
  std::string request_id, method, path, route;
  int status = 0;
  std::uint64_t bytes_in = 0, bytes_out = 0;
  std::int64_t vertices = -1, faces = -1;  // of the mesh(es), when the request got that far
  int parts = 0;
  double seconds = 0;
  std::string error_code;  // "" on success
};

void log_access(const AccessRecord& record);

}  // namespace wish::server
