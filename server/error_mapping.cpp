#include "server/error_mapping.hpp"

#include <array>
#include <atomic>
#include <new>

#include "wire/error_json.hpp"

namespace wish::server {

namespace {
std::atomic<int> g_retry_after{1};
}  // namespace

void set_retry_after_seconds(int seconds) { g_retry_after = seconds > 0 ? seconds : 1; }

// ErrorCategory -> HTTP status, the one table: http_status() below and scripts/gen-error-codes.py (which writes
// the statuses into proto/openapi.json) both read it, the script from this text, so keep one
// {ErrorCategory::Name, status} entry per category.
constexpr std::array<CategoryStatus, 9> kCategoryStatus{{
    {ErrorCategory::InvalidInput, 400},
    {ErrorCategory::UnsupportedFormat, 415},
    {ErrorCategory::TooLarge, 413},
    {ErrorCategory::Unmappable, 422},
    {ErrorCategory::NotFound, 404},
    {ErrorCategory::Timeout, 504},
    {ErrorCategory::Unavailable, 503},
    {ErrorCategory::Internal, 500},
    {ErrorCategory::Io, 500},  // the service's own files (models, reports): not the client's fault
}};

std::span<const CategoryStatus> category_statuses() { return kCategoryStatus; }

int http_status(ErrorCategory category) {
  for (const auto& entry : kCategoryStatus)
    if (entry.category == category) return entry.status;
  return 500;  // unreachable: every category has an entry (error_mapping_test)
}

ApiError to_api_error(const WishError& error) {
  ApiError out;
  out.status = http_status(error.category());
  out.code = error.code().empty() ? to_string(error.category()) : error.code();
  out.message = error.what();
  out.details = wire::details_json(error.details());
  if (out.status == 503) out.retry_after_seconds = g_retry_after.load();
  return out;
}

ApiError to_api_error(std::exception_ptr error) {
  try {
    if (error) std::rethrow_exception(error);
  } catch (const WishError& e) {
    return to_api_error(e);
  } catch (const std::bad_alloc&) {
    // Out of memory is a capacity problem of this server, not a bug in the request: ask the client to retry.
    return {503, "out_of_memory", "the server ran out of memory for this request", nlohmann::json::object(),
            g_retry_after.load()};
  } catch (const nlohmann::json::exception& e) {
    return {500, "internal", std::string("internal error while encoding JSON: ") + e.what(), nlohmann::json::object(), 0};
  } catch (const std::exception& e) {
    return {500, "internal", std::string("internal error: ") + e.what(), nlohmann::json::object(), 0};
  } catch (...) {
  }
  return {500, "internal", "internal error (unknown exception)", nlohmann::json::object(), 0};
}

ApiError unauthorized_error() {
  return {401, "unauthorized", "missing or wrong bearer token (Authorization: Bearer <token>)",
          nlohmann::json::object(), 0};
}

ApiError route_not_found_error(const std::string& method, const std::string& path) {
  return {404, "not_found", "no route " + method + " " + path, {{"method", method}, {"path", path}}, 0};
}

ApiError method_not_allowed_error(const std::string& method, const std::string& path, const std::string& allow) {
  return {405, "method_not_allowed", path + " does not take " + method + " (allowed: " + allow + ")",
          {{"method", method}, {"path", path}, {"allow", allow}}, 0};
}

ApiError status_error(int status) {
  switch (status) {
    case 413:
      return {413, "payload_too_large", "the request body exceeds the upload limit", nlohmann::json::object(), 0};
    case 414:
      return {414, "uri_too_long", "the request URI is too long", nlohmann::json::object(), 0};
    case 405:
      return {405, "method_not_allowed", "method not allowed on this route", nlohmann::json::object(), 0};
    case 404:
      return {404, "not_found", "no such route", nlohmann::json::object(), 0};
    case 503:
      return {503, "unavailable", "service unavailable", nlohmann::json::object(), g_retry_after.load()};
    default:
      break;
  }
  if (status >= 500) return {status, "internal", "internal error", nlohmann::json::object(), 0};
  return {status, "bad_request", "the request could not be read (framing, headers or body)", nlohmann::json::object(), 0};
}

nlohmann::json error_object(const ApiError& error) {
  return {{"code", error.code}, {"message", error.message}, {"details", error.details}};
}

nlohmann::json error_body(const ApiError& error, const std::string& request_id) {
  return {{"error", error_object(error)}, {"request_id", request_id}};
}

}  // namespace wish::server
