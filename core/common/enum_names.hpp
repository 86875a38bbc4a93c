#pragma once
// One table per enum for both directions, name -> value and value -> name, so that an enum's wire names are
// written once (model files, the CLI's options and the service's parameters all parse what to_string prints).
//
//   inline constexpr EnumNames<FitSolver, 2> kFitSolverNames{{{FitSolver::Direct, "direct"},
//                                                           {FitSolver::Banded, "banded"}}};
//   const char* to_string(FitSolver s) { return kFitSolverNames.name(s); }
//   FitSolver fit_solver_from_name(const std::string& n) { return kFitSolverNames.parse(n, "fit solver", "solver"); }
//
// A table that a front end lists (a CLI option's choices, an OpenAPI enum) is an `inline constexpr` in a small
// header beside the enum's (core/spherical_map/map_types.hpp, ...), so that adding a name to it is the only
// change: cli/enum_option.hpp builds the CLI validators from it and wire/contract_enums.cpp the OpenAPI enums.
//
// parse() throws InvalidInputError(code, "unknown fit solver 'x' (expected direct or banded)", {{detail_key, x}}):
// the expected list is made from the table, so it cannot fall out of date. The tests in
// tests/common/enum_names_test.cpp check that every table round-trips; an enum whose to_string is a switch (so that
// the compiler checks every enumerator is named) and that is never parsed keeps its switch.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/common/errors.hpp"

namespace wish {

template <class E, std::size_t N>
struct EnumNames {
  std::array<std::pair<E, const char*>, N> entries;

  constexpr const char* name(E value) const {
    for (const auto& [v, n] : entries)
      if (v == value) return n;
    return "?";  // an enumerator missing from its table: the round-trip test fails on it
  }

  // "a, b or c": the names in table order.
  std::string expected() const {
    std::string out;
    for (std::size_t i = 0; i < N; ++i) {
      if (i > 0) out += i + 1 == N ? " or " : ", ";
      out += entries[i].second;
    }
    return out;
  }

  // The names in table order: what a CLI validator accepts and what the OpenAPI enum of the type lists
  // (wire/contract_enums.cpp), so neither can fall out of date.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& entry : entries) out.emplace_back(entry.second);
    return out;
  }

  // The value named `text`, or nullopt: for callers that word their own refusal (the service's parameters).
  constexpr std::optional<E> find(std::string_view text) const {
    for (const auto& [v, n] : entries)
      if (text == n) return v;
    return std::nullopt;
  }

  E parse(std::string_view text, const char* what, const char* detail_key,
          const char* code = "invalid_parameter") const {
    for (const auto& [v, n] : entries)
      if (text == n) return v;
    const std::string given(text);
    throw InvalidInputError(code, "unknown " + std::string(what) + " '" + given + "' (expected " + expected() + ")",
                            {{detail_key, given}});
  }
};

}  // namespace wish
