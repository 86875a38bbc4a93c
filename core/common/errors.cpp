#include "core/common/errors.hpp"

namespace wish {

const char* to_string(ErrorCategory category) {
  switch (category) {
    case ErrorCategory::InvalidInput: return "invalid_input";
    case ErrorCategory::UnsupportedFormat: return "unsupported_format";
    case ErrorCategory::TooLarge: return "too_large";
    case ErrorCategory::Unmappable: return "unmappable";
    case ErrorCategory::NotFound: return "not_found";
    case ErrorCategory::Timeout: return "timeout";
    case ErrorCategory::Unavailable: return "unavailable";
    case ErrorCategory::Internal: return "internal";
    case ErrorCategory::Io: return "io";
  }
  return "internal";
}

WishError::WishError(ErrorCategory category, std::string code, const std::string& message, ErrorDetails details)
    : std::runtime_error(message), category_(category), code_(std::move(code)), details_(std::move(details)) {}

}  // namespace wish
