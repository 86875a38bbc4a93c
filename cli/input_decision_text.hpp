#pragma once
// The object-finding decision of a label volume (core/volume/input_kind.hpp) as the CLI shows it: one stderr line
// ("<volume>: input soft_mask, threshold 127.5: <why>") and one "warning:" line each, and the `input` block of the
// --json rows (the same fields as the service's volume.input).

#include <cstdio>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/volume/input_kind.hpp"

namespace wish::cli {

inline std::string threshold_text(const volume::InputDecision& d) {
  if (!d.threshold) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", *d.threshold);
  return b;
}

// `warnings_only`: --quiet still shows the warnings.
inline void print_input_decision(std::ostream& os, const std::string& name, const volume::InputDecision& d,
                                 bool warnings_only) {
  if (!warnings_only)
    os << name << ": input " << volume::to_string(d.kind)
       << (d.threshold ? ", threshold " + threshold_text(d) : std::string(", no threshold")) << ": " << d.why << "\n";
  for (const auto& w : d.warnings) os << name << ": warning: " << w << "\n";
}

inline nlohmann::json input_decision_json(const volume::InputDecision& d) {
  return {{"kind", volume::to_string(d.kind)},
          {"threshold", d.threshold ? nlohmann::json(*d.threshold) : nlohmann::json(nullptr)},
          {"why", d.why},
          {"warnings", d.warnings}};
}

}  // namespace wish::cli
