#pragma once
// Typed errors of the WISH core (pmp-library style): an exception carries a machine-readable code,
// a human message with the numbers that matter, and structured details. Numerical outcomes that are
// not bugs (did not converge, flipped triangles) are *status values* in result structs, not exceptions.
//
// The one table from ErrorCategory to an HTTP status lives in server/error_mapping.cpp (kCategoryStatus).

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <variant>

namespace wish {

// Broad class of an error; decides the HTTP status and the CLI exit code.
enum class ErrorCategory {
  InvalidInput,       // malformed file or bad parameter
  UnsupportedFormat,  // not OBJ/PLY/OFF/STL
  TooLarge,           // a configured limit was exceeded
  Unmappable,         // valid mesh that cannot be mapped to a sphere, or a map that failed verification
  NotFound,           // unknown model or resource
  Timeout,            // the per-request time limit passed
  Unavailable,        // queue full / shutting down
  Internal,           // a bug or an unexpected solver state
  Io,                 // a file could not be read or written: a named input missing, an output not writable (in the
                      // service a server error, whose own files these are; a distinct exit reason in the CLI)
};

const char* to_string(ErrorCategory category);

using ErrorDetailValue = std::variant<std::int64_t, double, std::string>;
using ErrorDetails = std::map<std::string, ErrorDetailValue>;

// Base of every exception thrown by core/. `code` is a stable snake_case identifier such as
// "genus_nonzero", "parse_error", "limit_exceeded", listed with its meaning in core/common/error_codes.hpp;
// `message` is a full sentence with numbers.
class WishError : public std::runtime_error {
 public:
  WishError(ErrorCategory category, std::string code, const std::string& message, ErrorDetails details = {});

  ErrorCategory category() const noexcept { return category_; }
  const std::string& code() const noexcept { return code_; }
  const ErrorDetails& details() const noexcept { return details_; }

 private:
  ErrorCategory category_;
  std::string code_;
  ErrorDetails details_;
};

// Convenience subclasses so `catch` sites and headers can say what they mean.
class InvalidInputError : public WishError {
 public:
  InvalidInputError(std::string code, const std::string& message, ErrorDetails details = {})
      : WishError(ErrorCategory::InvalidInput, std::move(code), message, std::move(details)) {}
};

class IoError : public WishError {
 public:
  IoError(std::string code, const std::string& message, ErrorDetails details = {})
      : WishError(ErrorCategory::Io, std::move(code), message, std::move(details)) {}
};

class LimitExceededError : public WishError {
 public:
  LimitExceededError(const std::string& message, ErrorDetails details = {})
      : WishError(ErrorCategory::TooLarge, "limit_exceeded", message, std::move(details)) {}
};

class TimeoutError : public WishError {
 public:
  TimeoutError(const std::string& message, ErrorDetails details = {})
      : WishError(ErrorCategory::Timeout, "timeout", message, std::move(details)) {}
};

}  // namespace wish
