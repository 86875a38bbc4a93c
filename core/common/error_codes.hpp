#pragma once
// The one list of error codes WISH reports (issue 16): every `code` a WishError carries, every code the HTTP front
// writes itself, and every per-object refusal code, each with its category and a one-line meaning.
//
// The list is checked from both sides (tests/common/error_codes_test.cpp): every code literal thrown anywhere in
// core/, server/ or cli/ must be listed here with the same category, and the enum of Error.code in
// proto/openapi.json must equal this list. Add a code here first, then throw it.
//
// Codes are stable snake_case identifiers: clients branch on them, so a code is never renamed silently.

#include <optional>
#include <span>
#include <string_view>

#include "core/common/errors.hpp"

namespace wish {

struct ErrorCodeInfo {
  std::string_view code;
  // The category a WishError with this code carries (decides the HTTP status, server/error_mapping.cpp). Empty for
  // codes only the HTTP transport writes (401 unauthorized, 405, 414, ...), which have no core category.
  std::optional<ErrorCategory> category;
  int transport_status = 0;  // HTTP status of a transport-only code; 0 otherwise
  std::string_view meaning;
};

// Every code, sorted by code.
std::span<const ErrorCodeInfo> error_codes();

// The entry of `code`, or nullptr when it is not listed.
const ErrorCodeInfo* find_error_code(std::string_view code);

}  // namespace wish
