#include "wire/training_report_json.hpp"

#include <Eigen/Core>

namespace wish::wire {

using json = nlohmann::json;

namespace {

json matrix_json(const Eigen::MatrixXd& m) {
  json out = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    out.push_back(row);
  }
  return out;
}

// Skipped cells (early stop) are NaN in mean/std: nlohmann writes NaN as null, which is what the report means.
json int_matrix_json(const Eigen::MatrixXi& m) {
  json out = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    out.push_back(row);
  }
  return out;
}

}  // namespace

nlohmann::json training_report_json(const TrainingReport& r) {
  json classes = json::array();
  for (std::size_t c = 0; c < r.classes.size(); ++c) classes.push_back({{"label", r.classes[c]}, {"count", r.class_counts[c]}});
  json per_class = json::array();
  for (const auto& m : r.test.per_class)
    per_class.push_back({{"label", m.label}, {"precision", m.precision}, {"recall", m.recall}, {"f1", m.f1}, {"support", m.support}});
  json confusion = json::array();
  for (Eigen::Index i = 0; i < r.test.confusion.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < r.test.confusion.cols(); ++j) row.push_back(r.test.confusion(i, j));
    confusion.push_back(row);
  }
  json chosen = json::array();
  for (const auto& [c, g] : r.nested.chosen) chosen.push_back({{"C", c}, {"gamma", g}});
  json test_samples = json::array();
  for (std::size_t i = 0; i < r.test_ids.size(); ++i)
    test_samples.push_back({{"id", r.test_ids[i]}, {"true", r.test_true[i]}, {"predicted", r.test_predicted[i]}});
  json losses = json::array();
  for (const auto& c : r.losses)
    losses.push_back({{"label", c.label}, {"meshes", c.total}, {"kept", c.kept}, {"lost", c.lost()},
                      {"lost_share", c.lost_share()}, {"flagged_off_recipe", c.flagged}, {"lost_by_code", c.lost_by_code}});
  json doc = {
      {"samples", r.samples},
      {"losses", losses},
      {"dataset_sha256", r.dataset_sha256},
      {"seed", r.seed},
      {"classes", classes},
      {"features",
       {{"family", to_string(r.spec.family)}, {"l_min", r.spec.l_min}, {"l_max", r.spec.l_max}, {"scale", to_string(r.spec.scale)},
        {"log", r.spec.log_transform}, {"global_scale_free", r.spec.global_scale_free}, {"names", r.feature_names}}},
      {"grid",
       {{"C", r.grid.Cs}, {"gamma", r.grid.gammas}, {"mean_accuracy", matrix_json(r.grid.mean_score)},
        {"std_accuracy", matrix_json(r.grid.std_score)}, {"best_C", r.grid.C()}, {"best_gamma", r.grid.gamma()},
        {"best_score", r.grid.best_score}, {"seconds", r.grid.seconds}, {"fits", r.grid.fits},
        {"capped_fits", int_matrix_json(r.grid.capped_fits)}, {"capped_fits_total", r.grid.total_capped_fits()},
        {"cells_skipped", r.grid.cells_skipped}, {"precomputed_kernel", r.grid.precomputed_kernel},
        {"narrow_fits", int_matrix_json(r.grid.narrow_fits)}, {"cells_offset_decided", r.grid.cells_offset_decided},
        {"best_offset_decided", r.grid.best_offset_decided},
        {"early_stop",
         {{"enabled", r.grid.early_stop}, {"drop", r.grid.early_stop_drop}, {"patience", r.grid.early_stop_patience}}},
        {"method", r.grid.method}, {"reason", r.search_reason}, {"search_rows", r.grid.search_rows}}},
      {"train_accuracy", r.train_accuracy},
      {"train_classes_never_predicted", r.train_classes_never_predicted},
      {"final_fit_capped_solvers", r.final_fit_cap_warnings},
      {"test",
       {{"samples", r.test_indices.size()}, {"accuracy", r.test.accuracy}, {"macro_f1", r.test.macro_f1},
        {"confusion_matrix", confusion}, {"confusion_rows", "true class"}, {"confusion_columns", "predicted class"},
        {"per_class", per_class}, {"predictions", test_samples}}},
      {"nested_cv",
       {{"folds", r.nested.scores.size()}, {"scores", r.nested.scores}, {"mean", r.nested.mean}, {"std", r.nested.std},
        {"chosen", chosen}, {"inner_best_scores", r.nested.inner_scores}, {"seconds", r.seconds_nested}, {"fits", r.nested.fits},
        {"capped_fits", r.nested.capped_fits}, {"cells_skipped", r.nested.cells_skipped},
        {"repeats", r.nested.repeats}, {"outer_folds", r.nested.outer_folds},
        {"interval95", r.nested.interval95 ? json::array({r.nested.interval95->low, r.nested.interval95->high}) : json()}}},
      {"seconds", r.seconds_total}};
  if (!r.grid.rungs.empty()) {
    json rungs = json::array();
    for (const auto& g : r.grid.rungs)
      rungs.push_back({{"rows", g.rows}, {"candidates", g.candidates}, {"splits", g.splits}, {"fits", g.fits}, {"seconds", g.seconds}});
    doc["grid"]["rungs"] = rungs;
    doc["grid"]["cell_rung"] = int_matrix_json(r.grid.cell_rung);
  }
  if (!r.test_novel.empty() || r.novelty_threshold > 0) {
    int flagged = 0;
    for (bool b : r.test_novel) flagged += b;
    json per_class = json::object();
    for (std::size_t c = 0; c < r.novelty_class_thresholds.size() && c < r.classes.size(); ++c)
      per_class[r.classes[c]] = r.novelty_class_thresholds[c];
    doc["novelty"] = {{"threshold", r.novelty_threshold}, {"class_thresholds", per_class}, {"quantile", r.novelty_quantile},
                      {"test_samples", r.test_novel.size()}, {"test_flagged", flagged}, {"test_scores", r.test_novelty}};
  }
  return doc;
}

json family_score_json(const FamilyScore& f) {
  return {{"family", f.family},        {"features", f.features},          {"best_C", f.C},
          {"best_gamma", f.gamma},     {"grid_score", f.grid_score},      {"test_accuracy", f.test_accuracy},
          {"nested_cv_mean", f.nested_mean}, {"nested_cv_std", f.nested_std},
          {"nested_cv_scores", f.nested_scores}, {"nested_cv_inner_best_scores", f.nested_inner_scores}};
}

json training_run_json(const TrainingReport& report, const TrainingRunInfo& run) {
  json doc = training_report_json(report);
  doc["input"] = run.input;
  doc["model_file"] = run.model_file;
  doc["model_sha256"] = run.model_sha256;
  json comparison = json::array();
  for (const auto& f : run.comparison) comparison.push_back(family_score_json(f));
  doc["comparison"] = comparison;
  json skipped = json::array();
  for (const auto& f : run.lost)
    skipped.push_back({{"file", f.id}, {"label", f.label}, {"code", f.code}, {"message", f.message}});
  for (const auto& f : run.unlabelled) skipped.push_back({{"file", f}, {"code", "no_label"}, {"message", "no label"}});
  doc["skipped"] = skipped;
  return doc;
}

}  // namespace wish::wire
