#include "server/api_response.hpp"

namespace wish::server {

const std::string* ApiResponse::header(const std::string& name) const {
  for (const auto& [key, value] : headers)
    if (key == name) return &value;
  return nullptr;
}

ApiResponse json_response(int status, const nlohmann::json& body) {
  ApiResponse out;
  out.status = status;
  out.body = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return out;
}

ApiResponse error_response(const ApiError& error, const std::string& request_id) {
  ApiResponse out = json_response(error.status, error_body(error, request_id));
  out.error_code = error.code;
  if (error.retry_after_seconds > 0) out.headers.emplace_back("Retry-After", std::to_string(error.retry_after_seconds));
  if (error.status == 401) out.headers.emplace_back("WWW-Authenticate", "Bearer");
  return out;
}

int batch_status(const std::vector<int>& part_statuses) {
  if (part_statuses.empty()) return 200;
  for (const int s : part_statuses)
    if (s != part_statuses.front()) return 207;
  return part_statuses.front();
}

}  // namespace wish::server
