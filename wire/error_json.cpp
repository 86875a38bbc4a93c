#include "wire/error_json.hpp"

#include <variant>

namespace wish::wire {

nlohmann::json details_json(const ErrorDetails& details) {
  nlohmann::json out = nlohmann::json::object();
  // The pair, not a structured binding, is captured: clang 14 (Debian 12; the sanitizer build) does not yet let a
  // lambda capture a structured binding (C++20, P1091).
  for (const auto& entry : details)
    std::visit([&](const auto& v) { out[entry.first] = v; }, entry.second);
  return out;
}

nlohmann::json error_entry_json(const WishError& error) {
  return {{"code", error.code()},
          {"category", to_string(error.category())},
          {"message", error.what()},
          {"details", details_json(error.details())}};
}

}  // namespace wish::wire
