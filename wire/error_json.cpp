#include "wire/error_json.hpp"

#include <variant>

namespace wish::wire {

nlohmann::json details_json(const ErrorDetails& details) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, value] : details)
    std::visit([&](const auto& v) { out[key] = v; }, value);
  return out;
}

nlohmann::json error_entry_json(const WishError& error) {
  return {{"code", error.code()},
          {"category", to_string(error.category())},
          {"message", error.what()},
          {"details", details_json(error.details())}};
}

}  // namespace wish::wire
