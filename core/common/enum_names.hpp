#pragma once
// One table per enum for both directions, name -> value and value -> name, so that an enum's wire names are
// written once (model files, the CLI's options and the service's parameters all parse what to_string prints).
//
//   inline constexpr EnumNames<FitSolver, 2> kFitSolverNames{{{FitSolver::Direct, "direct"},
//                                                           {FitSolver::Banded, "banded"}}};
//   const char* to_string(FitSolver s) { return kFitSolverNames.name(s); }
//   FitSolver fit_solver_from_name(const std::string& n) { return kFitSolverNames.parse(n, "fit solver", "solver"); }
//
// parse() throws InvalidInputError(code, "unknown fit solver 'x' (expected direct or banded)", {{detail_key, x}}):
// the expected list is made from the table, so it cannot fall out of date. The tests in
// tests/common/enum_names_test.cpp check that every table round-trips; an enum whose to_string is a switch (so that
// the compiler checks every enumerator is named) and that is never parsed keeps its switch.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

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
