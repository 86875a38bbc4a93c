#pragma once
// The JSON of an error and its details, for every front end: the service's error bodies (server/error_mapping.hpp
// adds the HTTP status), the validation issues of a mesh report (wire_json.hpp) and the CLI's per-file rows.
// Eigen-free and httplib-free.

#include <nlohmann/json.hpp>

#include "core/common/errors.hpp"

namespace wish::wire {

// ErrorDetails (ErrorDetailValue: integer, number or string per key) -> a JSON object of the same keys.
nlohmann::json details_json(const ErrorDetails& details);
// A failed file in the CLI's JSON output (`wish inspect`, `wish describe`): {"code", "category", "message", "details"}.
nlohmann::json error_entry_json(const WishError& error);

}  // namespace wish::wire
