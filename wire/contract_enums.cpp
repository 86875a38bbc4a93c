#include "wire/contract_enums.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/classify/recipe_names.hpp"
#include "core/geometry/laplacian_kind_names.hpp"
#include "core/sh/sh_fit_names.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/volume/object_mode.hpp"

namespace wish::wire {

namespace {

template <class E, std::size_t N>
ContractEnum from_table(const char* schema, const EnumNames<E, N>& table, const std::string& what, const char* where) {
  return {schema, table.names(),
          what + " (generated from the core name table in " + where + " by wire/contract_enums.cpp; do not edit)"};
}

// The index just past the JSON value (an object, array or string here) that starts at `start`.
std::size_t end_of_value(const std::string& text, std::size_t start) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = start; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') {
        in_string = false;
        if (depth == 0) return i + 1;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      ++depth;
    } else if (c == '}' || c == ']') {
      if (--depth == 0) return i + 1;
    }
  }
  throw std::runtime_error("openapi document: unbalanced JSON value at offset " + std::to_string(start));
}

}  // namespace

std::vector<ContractEnum> contract_enums() {
  return {
      from_table("MapMethod", kMapMethodNames, "Spherical-map method", "core/spherical_map/map_types.hpp"),
      from_table("FitWeighting", kFitWeightingNames, "SH fit weights: input vertex areas or uniform (the paper's)",
                 "core/sh/sh_fit_names.hpp"),
      from_table("FitSolver", kFitSolverNames, "SH fit solver: one LDLT solve or the paper's banded residual scheme",
                 "core/sh/sh_fit_names.hpp"),
      from_table("GramMethod", kGramMethodNames, "How the SH fit's Gram matrix is built", "core/sh/sh_fit_names.hpp"),
      from_table("LaplacianKind", geometry::kLaplacianKindNames, "Cotan Laplacian of the map's operator",
                 "core/geometry/laplacian_kind_names.hpp"),
      from_table("OffRecipePolicy", kOffRecipePolicyNames,
                 "What a model does with a descriptor whose map came from another method than its recipe's: refuse "
                 "(422 off_recipe) or predict with recipe_match false",
                 "core/classify/recipe_names.hpp"),
      from_table("ObjectMode", volume::kObjectModeNames,
                 "How a label volume's objects are found: auto (decided from the values), labels (each value one "
                 "object) or components (6-connected parts of a mask)",
                 "core/volume/object_mode.hpp"),
  };
}

std::string contract_enum_json(const ContractEnum& e) {
  std::string names;
  for (const auto& n : e.names) names += (names.empty() ? "" : ", ") + nlohmann::json(n).dump();
  return "{ \"type\": \"string\", \"enum\": [" + names + "], \"description\": " + nlohmann::json(e.description).dump() +
         " }";
}

std::string with_contract_enums(const std::string& openapi) {
  std::string text = openapi;
  const std::string anchor = "\"schemas\": {";
  const auto schemas = text.find(anchor);
  if (schemas == std::string::npos) throw std::runtime_error("openapi document: no components/schemas object");
  std::string inserted;
  for (const ContractEnum& e : contract_enums()) {
    // A key is looked for only inside the components/schemas object (whose end moves as values are replaced).
    const std::size_t schemas_end = end_of_value(text, schemas + anchor.size() - 1);
    const std::string key = "\"" + e.schema + "\": ";
    const std::size_t at = text.find(key, schemas);
    if (at != std::string::npos && at < schemas_end) {
      const std::size_t value = at + key.size();
      text.replace(value, end_of_value(text, value) - value, contract_enum_json(e));
    } else {
      inserted += "\n      " + key + contract_enum_json(e) + ",";
    }
  }
  text.insert(schemas + anchor.size(), inserted);
  return text;
}

}  // namespace wish::wire
