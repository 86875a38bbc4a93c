#pragma once
// What `wish train` runs at each size (issue 40): the paper's search and evaluation (paper §6: the 13 x 13 grid, 10
// stratified shuffle splits per cell, nested CV 2 x 5) cost about n^2.7 in the number of samples n, so above a size
// the default changes path, and the training report says which path ran and why (docs/benchmarks.md "Training that
// scales" has the measurements these thresholds come from):
//  * search: the full grid (grid_search.hpp, early stop) while the search's training rows are at most
//    `halving_above_rows`; above, successive halving over the same grid (successive_halving.hpp), its last rung on at
//    most `halving.max_rows` rows, the model then fitted on all training rows.
//  * nested CV: `nested_repeats` repeats of the outer folds while the samples are at most `single_repeat_above`;
//    above, one repeat (every sample predicted once), its 95 % interval stated (metrics.hpp, cv_interval).
// --search grid / halving forces a path whatever the size.

#include <string>

#include "core/classify/successive_halving.hpp"
#include "core/common/enum_names.hpp"

namespace wish {

enum class SearchMethod { Auto, Grid, Halving };

inline constexpr EnumNames<SearchMethod, 3> kSearchMethodNames{{{
    {SearchMethod::Auto, "auto"}, {SearchMethod::Grid, "grid"}, {SearchMethod::Halving, "halving"}}}};

const char* to_string(SearchMethod method);
SearchMethod search_method_from_name(const std::string& name);  // InvalidInputError("training_parameters")

struct ScalePolicy {
  SearchMethod search = SearchMethod::Auto;
  int halving_above_rows = 1200;  // auto: halving when the search has more training rows than this
  HalvingOptions halving;
  int single_repeat_above = 2500;  // auto: above this many samples, one repeat of the nested CV's outer folds
};

struct TrainingPlan {
  SearchMethod search = SearchMethod::Grid;  // Grid or Halving, never Auto
  std::string search_reason;
  int nested_repeats = 0;
  std::string nested_reason;
};

// samples: the training set; search_rows: the rows the search sees (the hold-out split's training side);
// nested_repeats: the repeats asked for (0: no nested CV).
TrainingPlan plan_training(int samples, int search_rows, int nested_repeats, const ScalePolicy& policy);

// What the default does at each size, in words (the footer of `wish train --help`).
std::string training_scale_help(const ScalePolicy& policy);

}  // namespace wish
