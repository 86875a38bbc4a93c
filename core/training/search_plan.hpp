#pragma once
// What `wish train` runs at each size (issue 40): the paper's search and evaluation (paper §6: the 13 x 13 grid, 10
// stratified shuffle splits per cell, nested CV 2 x 5) cost about n^2.7 in the number of samples n, so above a size
// the default changes path, and the training report says which path ran and why (docs/benchmarks.md "Training that
// scales" has the measurements these thresholds come from):
//  * search: the full grid (grid_search.hpp, early stop) while the search's training rows are at most
//    `halving_above_rows`; above, successive halving over the same grid (successive_halving.hpp), its last rung on at
//    most `halving.max_rows` rows, the model then fitted on all training rows.
//  * nested CV: the paper's repeats x folds at every size, the inner searches on the main search's path; its 95 %
//    interval is stated (cv_interval.hpp). One repeat above a size was measured and not needed: the whole default
//    train at 30,000 samples took 228 CPU s with 2 x 5 against 162 with 1 x 5 (--nested-repeats 1 does it); with
//    today's default features 430 CPU s, 259 s wall on 2 cores (docs/benchmarks.md "Training that scales").
// --search grid / halving forces a path whatever the size.

#include <string>

#include "core/common/enum_names.hpp"
#include "core/training/successive_halving.hpp"

namespace wish {

enum class SearchMethod { Auto, Grid, Halving };

inline constexpr EnumNames<SearchMethod, 3> kSearchMethodNames{{{
    {SearchMethod::Auto, "auto"}, {SearchMethod::Grid, "grid"}, {SearchMethod::Halving, "halving"}}}};

const char* to_string(SearchMethod method);
SearchMethod search_method_from_name(const std::string& name);  // InvalidInputError("training_parameters")

struct ScalePolicy {
  SearchMethod search = SearchMethod::Auto;
  int halving_above_rows = 800;  // auto: halving above this many search rows (1,000 samples with a 20 % test split)
  HalvingOptions halving;
};

struct SearchPlan {
  SearchMethod search = SearchMethod::Grid;  // Grid or Halving, never Auto
  std::string reason;
};

// search_rows: the rows the search sees (the hold-out split's training side; the nested CV's outer training folds
// are as large, so its inner searches take the same path).
SearchPlan plan_search(int search_rows, const ScalePolicy& policy);

// What the default does at each size, in words (the footer of `wish train --help`).
std::string training_scale_help(const ScalePolicy& policy);

}  // namespace wish
