#include "core/classify/search_plan.hpp"

#include <algorithm>

namespace wish {

const char* to_string(SearchMethod method) { return kSearchMethodNames.name(method); }

SearchMethod search_method_from_name(const std::string& name) {
  return kSearchMethodNames.parse(name, "search method", "search", "training_parameters");
}

TrainingPlan plan_training(int samples, int search_rows, int nested_repeats, const ScalePolicy& policy) {
  TrainingPlan plan;
  const std::string rows = std::to_string(search_rows) + " training rows";
  switch (policy.search) {
    case SearchMethod::Grid:
      plan.search = SearchMethod::Grid;
      plan.search_reason = "full grid: asked for (--search grid), " + rows;
      break;
    case SearchMethod::Halving:
      plan.search = SearchMethod::Halving;
      plan.search_reason = "successive halving: asked for (--search halving), " + rows;
      break;
    case SearchMethod::Auto:
      if (search_rows > policy.halving_above_rows) {
        plan.search = SearchMethod::Halving;
        plan.search_reason = "successive halving: " + rows + " > " + std::to_string(policy.halving_above_rows) +
                             " (the full grid grows about as n^2.7); last rung on up to " +
                             std::to_string(policy.halving.max_rows) + " rows, the model fitted on all " +
                             std::to_string(search_rows);
      } else {
        plan.search = SearchMethod::Grid;
        plan.search_reason = "full grid: " + rows + " <= " + std::to_string(policy.halving_above_rows);
      }
      break;
  }
  plan.nested_repeats = nested_repeats;
  if (nested_repeats > 1 && policy.search == SearchMethod::Auto && samples > policy.single_repeat_above) {
    plan.nested_repeats = 1;
    plan.nested_reason = "one repeat of the outer folds: " + std::to_string(samples) + " samples > " +
                         std::to_string(policy.single_repeat_above) + " (asked: " + std::to_string(nested_repeats) +
                         " repeats); the 95 % interval states the estimate's uncertainty";
  } else if (nested_repeats > 0) {
    plan.nested_reason = std::to_string(nested_repeats) + " repeat" + (nested_repeats > 1 ? "s" : "") + " of the outer folds";
  }
  return plan;
}

std::string training_scale_help(const ScalePolicy& policy) {
  const HalvingOptions& h = policy.halving;
  return "What the default does at each size (docs/benchmarks.md \"Training that scales\"; the report says which path "
         "ran and why):\n"
         "  up to " + std::to_string(policy.halving_above_rows) + " training rows (the samples less the 20 % test "
         "split): the paper's full grid, every C x gamma cell on all rows (early stop along C);\n"
         "  above: successive halving over the same grid: every cell on a small stratified subsample, the best 1/" +
         std::to_string(h.factor) + " on " + std::to_string(h.factor) + "x the rows, ..., the last few cells on " +
         std::to_string(h.max_rows) + " rows; the model is fitted on all training rows;\n"
         "  nested CV: --nested-repeats x --nested-folds up to " +
         std::to_string(policy.single_repeat_above) + " samples, one repeat above (every sample predicted once), with "
         "its 95 % interval.\n"
         "--search grid keeps the paper's protocol (full grid, all repeats) at any size.";
}

}  // namespace wish
