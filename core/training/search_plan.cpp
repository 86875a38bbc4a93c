#include "core/training/search_plan.hpp"

#include <algorithm>

namespace wish {

const char* to_string(SearchMethod method) { return kSearchMethodNames.name(method); }

SearchMethod search_method_from_name(const std::string& name) {
  return kSearchMethodNames.parse(name, "search method", "search", "training_parameters");
}

SearchPlan plan_search(int search_rows, const ScalePolicy& policy) {
  SearchPlan plan;
  const std::string rows = std::to_string(search_rows) + " training rows";
  switch (policy.search) {
    case SearchMethod::Grid:
      plan.search = SearchMethod::Grid;
      plan.reason = "full grid: asked for (--search grid), " + rows;
      break;
    case SearchMethod::Halving:
      plan.search = SearchMethod::Halving;
      plan.reason = "successive halving: asked for (--search halving), " + rows;
      break;
    case SearchMethod::Auto:
      if (search_rows > policy.halving_above_rows) {
        plan.search = SearchMethod::Halving;
        plan.reason = "successive halving: " + rows + " > " + std::to_string(policy.halving_above_rows) +
                      " (the full grid's cost grows about as n^2.7); last rung on up to " +
                      std::to_string(policy.halving.max_rows) + " rows, the model fitted on all " +
                      std::to_string(search_rows);
      } else {
        plan.search = SearchMethod::Grid;
        plan.reason = "full grid: " + rows + " <= " + std::to_string(policy.halving_above_rows);
      }
      break;
  }
  return plan;
}

std::string training_scale_help(const ScalePolicy& policy) {
  const HalvingOptions& h = policy.halving;
  return "What the default does at each size (docs/benchmarks.md \"Training that scales\"; the report says which\n"
         "search ran and why):\n"
         "  up to " + std::to_string(policy.halving_above_rows) + " training rows (" +
         std::to_string(policy.halving_above_rows * 5 / 4) + " samples with the 20 % test split): the paper's\n"
         "    full grid, every C x gamma cell on all training rows (early stop along C);\n"
         "  above: successive halving over the same grid: every cell on a small stratified subsample, the best\n"
         "    1/" + std::to_string(h.factor) + " on " + std::to_string(h.factor) + "x the rows, and so on, the last few on " +
         std::to_string(h.max_rows) + " rows; the model is then fitted on all training rows;\n"
         "  nested CV: --nested-repeats x --nested-folds at every size, its inner searches on the same path, with\n"
         "    its 95 % interval.\n"
         "--search grid runs the full grid at any size, --search halving halving at any size.";
}

}  // namespace wish
