#pragma once
// The one place where an error becomes an HTTP status and the one JSON error body
// {"error": {"code", "message", "details"}, "request_id"} (Triton / llama.cpp server lesson: the core throws typed
// WishErrors and knows nothing about HTTP; the front end maps them here and nowhere else).
// Eigen-free and httplib-free, so both the HTTP file and the compute side may include it.

#include <exception>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "core/common/errors.hpp"

namespace wish::server {

struct ApiError {
  int status = 500;
  std::string code = "internal";
  std::string message;
  nlohmann::json details = nlohmann::json::object();
  int retry_after_seconds = 0;  // > 0: send a Retry-After header (503)
};

// ErrorCategory -> HTTP status: one table (error_mapping.cpp), which scripts/gen-error-codes.py also reads.
struct CategoryStatus {
  ErrorCategory category;
  int status;
};
std::span<const CategoryStatus> category_statuses();
int http_status(ErrorCategory category);

// Seconds a client should wait before retrying a 503; set once at start from the configuration.
void set_retry_after_seconds(int seconds);

ApiError to_api_error(const WishError& error);
// Maps whatever is in flight: WishError by category, std::bad_alloc -> 503, anything else -> 500 (a bug).
ApiError to_api_error(std::exception_ptr error);

// Errors that originate in the HTTP layer itself, not in core (statuses still decided only in this file).
ApiError unauthorized_error();
ApiError route_not_found_error(const std::string& method, const std::string& path);
// 405: a known path, another method; `allow` is the Allow header's value ("GET, HEAD").
ApiError method_not_allowed_error(const std::string& method, const std::string& path, const std::string& allow);
ApiError status_error(int status);  // a bare status from the HTTP library (e.g. 413 payload, 400 framing)

nlohmann::json error_object(const ApiError& error);  // {"code", "message", "details"}
nlohmann::json error_body(const ApiError& error, const std::string& request_id);

}  // namespace wish::server
