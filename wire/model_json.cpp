#include "wire/model_json.hpp"

#include <chrono>
#include <ctime>

#include "core/classify/feature_pipeline.hpp"
#include "core/classify/model_json_codec.hpp"

namespace wish::wire {

namespace {

std::string now_iso8601() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The model file's class spectra plus l_min (the degree of each array's first entry), for clients that draw them.
nlohmann::json class_spectra_with_l_min(const std::vector<ClassSpectrum>& spectra) {
  nlohmann::json out = class_spectra_to_json(spectra);
  for (auto& c : out) c["l_min"] = 1;
  return out;
}

}  // namespace

nlohmann::json model_info_json(const ClassifierModel& m, const std::filesystem::path& file) {
  const auto& ds = m.recipe();
  const auto& fs = m.feature_spec();
  const auto& ts = m.training_summary();
  return {
      {"name", m.name()},
      {"version", m.version()},
      {"file", file.filename().string()},
      {"loaded_at", now_iso8601()},
      {"classes", m.classes()},
      {"descriptor_settings",
       {{"lmax", ds.sh.lmax},
        {"method", to_string(ds.map.method)},
        {"steps", model_steps(ds)},
        {"regularization", ds.sh.regularization},
        {"weighting", to_string(ds.sh.weighting)},
        {"solver", to_string(ds.sh.solver)},
        {"tau", ds.map.willmore.tau},
        {"filtered", ds.map.willmore.filtered},
        {"fallback", ds.map.fallback},
        {"off_recipe", to_string(ds.off_recipe)}}},
      {"recipe", recipe_to_json(ds)},
      {"feature_spec",
       {{"family", to_string(fs.family)},
        {"l_min", fs.l_min},
        {"l_max", fs.l_max},
        {"scale", to_string(fs.scale)},
        {"log_transform", fs.log_transform}}},
      {"training_summary",
       {{"dataset_sha256", ts.dataset_sha256},
        {"trained_at", ts.trained_at},
        {"samples", ts.samples},
        {"best_c", ts.best_c},
        {"best_gamma", ts.best_gamma},
        {"grid_score", ts.grid_score},
        {"test_accuracy", ts.test_accuracy},
        {"nested_cv_mean", ts.nested_cv_mean},
        {"nested_cv_std", ts.nested_cv_std},
        {"notes", ts.notes},
        {"class_spectra", class_spectra_with_l_min(ts.class_spectra)}}},
  };
}

}  // namespace wish::wire
