// The model file (docs/design/classification.md "The model on disk"): one versioned, self-describing JSON document
//   { "format": "wish-classifier", "format_version": 2, "payload": {...}, "payload_sha256": "<hex>" }
// The payload holds the classes, the descriptor recipe (payload.recipe: recipe_version, map, sh, features with
// their column names, off_recipe policy; descriptor_recipe.hpp), the scaler, the SVM (parameters, support vectors, coefficients, rho,
// probA/probB) and the training summary. The seal is the SHA-256 of payload.dump() — nlohmann::json sorts keys
// and prints doubles in their shortest round-trip form, so the dump is canonical and survives a parse.
// A converter that edits a model on purpose (clients/) recomputes the seal the same way.
// Every key is one this build knows (issue 27): an unknown key anywhere is refused (model_version, with its path),
// because a reader that skipped it would compute with its own value of a setting the file states.
#include <fstream>
#include <set>
#include <type_traits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"
#include "core/classify/classifier_state.hpp"
#include "core/classify/descriptor_recipe_codec.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/classify/model_json_codec.hpp"
#include "core/classify/novelty.hpp"
#include "core/classify/sha256.hpp"
#include "core/common/errors.hpp"

namespace wish {
namespace {

using nlohmann::json;
constexpr const char* kFormatName = "wish-classifier";

[[noreturn]] void invalid(const std::string& message) {
  throw InvalidInputError("model_invalid", "invalid model file: " + message);
}


// ---- strict readers: every field required, with its path in the message ----
const json& field(const json& j, const std::string& key, const std::string& where) {
  if (!j.is_object()) invalid(where + " is not an object");
  auto it = j.find(key);
  if (it == j.end()) invalid("missing field " + where + "." + key);
  return *it;
}
double num(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_number()) invalid(where + "." + key + " is not a number");
  return v.get<double>();
}
std::int64_t integer(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_number_integer()) invalid(where + "." + key + " is not an integer");
  return v.get<std::int64_t>();
}
bool boolean(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_boolean()) invalid(where + "." + key + " is not true/false");
  return v.get<bool>();
}
std::string str(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_string()) invalid(where + "." + key + " is not a string");
  return v.get<std::string>();
}
std::vector<double> numbers(const json& v, const std::string& where) {
  if (!v.is_array()) invalid(where + " is not an array");
  std::vector<double> out;
  out.reserve(v.size());
  for (const auto& x : v) {
    if (!x.is_number()) invalid(where + " contains a non-number");
    out.push_back(x.get<double>());
  }
  return out;
}
std::vector<int> ints(const json& v, const std::string& where) {
  if (!v.is_array()) invalid(where + " is not an array");
  std::vector<int> out;
  for (const auto& x : v) {
    if (!x.is_number_integer()) invalid(where + " contains a non-integer");
    out.push_back(x.get<int>());
  }
  return out;
}
Eigen::MatrixXd matrix(const json& v, Eigen::Index cols, const std::string& where) {
  if (!v.is_array()) invalid(where + " is not an array of rows");
  Eigen::MatrixXd m(static_cast<Eigen::Index>(v.size()), cols);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::vector<double> row = numbers(v[i], where + "[" + std::to_string(i) + "]");
    if (static_cast<Eigen::Index>(row.size()) != cols)
      invalid(where + "[" + std::to_string(i) + "] has " + std::to_string(row.size()) + " entries, expected " +
              std::to_string(cols));
    for (Eigen::Index c = 0; c < cols; ++c) m(static_cast<Eigen::Index>(i), c) = row[c];
  }
  return m;
}
json to_array(const Eigen::VectorXd& v) { return json(std::vector<double>(v.data(), v.data() + v.size())); }
json rows(const Eigen::MatrixXd& m) {
  json out = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) out.push_back(to_array(m.row(i).transpose()));
  return out;
}

// An object's keys against the keys a reader of this build knows: any other key is refused, because a reader
// that skipped it would compute with its own value of a setting the file states (a newer build's field, or an
// edit). Named with its path; ClassifierModel::load adds the file.
void refuse_unknown_keys(const json& j, const std::set<std::string>& known, const std::string& where) {
  if (!j.is_object()) return;
  for (const auto& [key, value] : j.items()) {
    if (known.count(key)) continue;
    throw InvalidInputError("model_version",
                            "unknown key " + where + "." + key + ": this build reads model format " +
                                std::to_string(ClassifierModel::kFormatVersion) + " with descriptor recipe versions 1.." +
                                std::to_string(DescriptorRecipe::kVersion) +
                                " and no such field (written by a newer wish, or edited by hand)",
                            {{"key", where + "." + key}});
  }
}

// Writes the fields visit_recipe() lists for a file of recipe version `version` (recipe_version_of).
struct SettingsWriter {
  json& out;
  int version;
  template <class T> void field(const char* key, const T& value) {
    if constexpr (std::is_enum_v<T>) out[key] = to_string(value);
    else out[key] = value;
  }
  template <class F> void group(const char* key, F&& fill) {
    SettingsWriter sub{out[key], version};
    fill(sub);
  }
  template <class T> void added(int since, const char* key, const T& value, const T&) {
    if (since <= version) field(key, value);
  }
  template <class F, class T> void added_group(int since, const char* key, F&& fill, const T&, const T&) {
    if (since <= version) group(key, fill);
  }
  template <class T> void retired(const char*, int, const T&) {}
  void derived(const char*) {}  // recipe_to_json writes them
};

// Reads every field visit_recipe() lists for the file's recipe version; a missing, mistyped or unknown field is
// refused with its path.
struct SettingsReader {
  const json& in;
  std::string where;
  int version;                   // the file's recipe_version
  std::set<std::string> known;   // keys of `in` that a field of the table read

  void field(const char* key, double& value) { value = num(in, mark(key), where); }
  void field(const char* key, int& value) { value = static_cast<int>(integer(in, mark(key), where)); }
  void field(const char* key, bool& value) { value = boolean(in, mark(key), where); }
  template <class E> requires std::is_enum_v<E> void field(const char* key, E& value) {
    const std::string name = str(in, mark(key), where);
    try {
      value = enum_from_name(name, value);
    } catch (const WishError&) {
      invalid(where + "." + key + " '" + name + "' is unknown");
    }
  }
  template <class F> void group(const char* key, F&& fill) {
    SettingsReader sub{wish::field(in, mark(key), where), where + "." + key, version, {}};
    fill(sub);
    sub.finish();
  }
  template <class T> void added(int since, const char* key, T& value, const T& legacy) {
    if (takes_legacy(since, key)) value = legacy;
    else field(key, value);
  }
  template <class F, class T> void added_group(int since, const char* key, F&& fill, T& target, const T& legacy) {
    if (takes_legacy(since, key)) target = legacy;
    else group(key, fill);
  }
  template <class T> void retired(const char* key, int last_version, const T& value_today) {
    if (!in.is_object() || !in.contains(key) || version > last_version) return;  // a later file: an unknown key
    T value{};
    field(key, value);
    if (value != value_today)
      throw InvalidInputError("model_version", where + "." + key + " = " + in.at(key).dump() +
                                                   ": this setting was retired, and this build computes as with " +
                                                   json(value_today).dump());
  }
  void derived(const char* key) { mark(key); }  // checked by recipe_from_json
  // After every field was read: any key left is unknown.
  void finish(std::set<std::string> also_known = {}) {
    also_known.insert(known.begin(), known.end());
    refuse_unknown_keys(in, also_known, where);
  }

 private:
  const std::string& mark(const char* key) { return *known.insert(key).first; }
  // A file without the key takes the legacy value when its version predates the field, or when it was written
  // before versions were computed (files of versions 1..2 lacked fields their builds already had). A file of a
  // computed version holds every field of its version: one missing there is refused like any other.
  bool takes_legacy(int since, const char* key) const {
    if (in.is_object() && in.contains(key)) return false;
    return version < DescriptorRecipe::kFirstComputedVersion || since > version;
  }
  static MapMethod enum_from_name(const std::string& n, MapMethod) { return map_method_from_name(n); }
  static LinearSolverKind enum_from_name(const std::string& n, LinearSolverKind) { return linear_solver_from_name(n); }
  static FitWeighting enum_from_name(const std::string& n, FitWeighting) { return fit_weighting_from_name(n); }
  static FitSolver enum_from_name(const std::string& n, FitSolver) { return fit_solver_from_name(n); }
  static GramMethod enum_from_name(const std::string& n, GramMethod) { return gram_method_from_name(n); }
  static FeatureFamily enum_from_name(const std::string& n, FeatureFamily) { return feature_family_from_name(n); }
  static ScaleNormalization enum_from_name(const std::string& n, ScaleNormalization) {
    return scale_normalization_from_name(n);
  }
  static OffRecipePolicy enum_from_name(const std::string& n, OffRecipePolicy) { return off_recipe_policy_from_name(n); }
  static AreaCorrection enum_from_name(const std::string& n, AreaCorrection) { return area_correction_from_name(n); }
  static CanonicalMap enum_from_name(const std::string& n, CanonicalMap) { return canonical_map_from_name(n); }
  static spherical::DistortionEnergyKind enum_from_name(const std::string& n, spherical::DistortionEnergyKind) {
    return spherical::distortion_energy_from_name(n);
  }
  static FitSampling enum_from_name(const std::string& n, FitSampling) { return fit_sampling_from_name(n); }
  static geometry::LaplacianKind enum_from_name(const std::string& n, geometry::LaplacianKind) {
    return geometry::laplacian_kind_from_name(n.c_str());
  }
};

DescriptorRecipe recipe_from_json(const json& j) {
  const std::int64_t version = integer(j, "recipe_version", "payload.recipe");
  if (version < 1 || version > DescriptorRecipe::kVersion)
    throw InvalidInputError("model_version",
                            "descriptor recipe version " + std::to_string(version) + " is not supported (this build reads versions 1.." +
                                std::to_string(DescriptorRecipe::kVersion) +
                                (version > DescriptorRecipe::kVersion ? "; the file was written by a newer wish" : "") + ")",
                            {{"version", version}, {"supported", std::int64_t{DescriptorRecipe::kVersion}}});
  DescriptorRecipe r;
  SettingsReader reader{j, "payload.recipe", static_cast<int>(version), {}};
  visit_recipe(reader, r);
  reader.finish({"recipe_version"});
  if (r.sh.lmax < kShMinFitLmax || r.sh.lmax > kShMaxFitLmax)
    invalid("recipe.sh.lmax " + std::to_string(r.sh.lmax) + " is out of the SH fit's range " +
            std::to_string(kShMinFitLmax) + ".." + std::to_string(kShMaxFitLmax));
  const json& names = field(field(j, "features", "recipe"), "names", "recipe.features");
  if (names != json(feature_names(r.features)))
    invalid("recipe.features.names do not match the feature pipeline (" + names.dump() + ")");
  return r;
}

// Format 1 -> 2: payload.descriptor {map, sh} and payload.features became payload.recipe {map, sh, features,
// off_recipe, recipe_version}. Version-1 code predicted from any verified map, whatever method the fallback chain
// ended on, so the migrated policy is accept_flagged: the model predicts as before, and now says when it did so
// from an off-recipe map.
json migrate_v1_payload(json p) {
  if (!p.is_object()) invalid("payload is not an object");
  refuse_unknown_keys(p, {"name", "version", "classes", "descriptor", "features", "scaler", "svm", "training"},
                      "payload");
  json recipe = field(p, "descriptor", "payload");
  if (!recipe.is_object()) invalid("payload.descriptor is not an object");
  refuse_unknown_keys(recipe, {"map", "sh"}, "payload.descriptor");
  recipe["features"] = field(p, "features", "payload");
  recipe["off_recipe"] = to_string(OffRecipePolicy::AcceptFlagged);
  recipe["recipe_version"] = 1;
  p.erase("descriptor");
  p.erase("features");
  p["recipe"] = std::move(recipe);
  return p;
}

// Optional: model files written before class spectra existed have none (the payload seal covers what is there).
std::vector<ClassSpectrum> class_spectra_from_json(const json& t) {
  std::vector<ClassSpectrum> out;
  if (!t.contains("class_spectra")) return out;
  const json& arr = t.at("class_spectra");
  if (!arr.is_array()) invalid("training.class_spectra is not an array");
  for (const auto& c : arr) {
    refuse_unknown_keys(c, {"label", "count", "log_xi_mean", "log_xi_std"}, "payload.training.class_spectra[]");
    ClassSpectrum s;
    s.label = str(c, "label", "class_spectra");
    s.count = integer(c, "count", "class_spectra");
    s.log_xi_mean = numbers(field(c, "log_xi_mean", "class_spectra"), "class_spectra.log_xi_mean");
    s.log_xi_std = numbers(field(c, "log_xi_std", "class_spectra"), "class_spectra.log_xi_std");
    if (s.log_xi_mean.size() != s.log_xi_std.size()) invalid("class_spectra: log_xi_mean and log_xi_std differ in length");
    out.push_back(std::move(s));
  }
  return out;
}

json payload_without_novelty(const ClassifierModel::State& s);

// Optional block (issue 25): the novelty calibration (novelty.hpp).
//  format 3: one reference set — {k, quantile, reference, loo_scores: [...]};
//  format 4: per class — {k, quantile, reference, reference_classes: [class index per row],
//            loo_scores: [[...] per class]}.
//  format 5: format 4's keys and whitening: [[...] per feature] (the symmetric matrix W of novelty.hpp).
//  format 6: format 5's keys and calibration_folds (>= 2: loo_scores are cross-validated scores, novelty.hpp).
//  format 7: format 6's keys and rule: "predicted_class" (novelty.hpp NoveltyRule; written only for that rule).
//  format 8: the same keys; rule may also be "median_scale" (issue 38; a format-7 reader refuses the file by number).
//            A format-6 block without whitening (a Euclidean figure, cross-validated) is written as 6 too.
// Each format's keys are exactly its own: a format-3 reader meets reference_classes and refuses the file by it
// (model_version), and this build reads a format-3 block as the one-set figure it was written as.
json novelty_to_json(const NoveltyCalibration& c) {
  json j = {{"k", c.k}, {"quantile", c.quantile}, {"reference", rows(c.reference)}};
  if (c.per_class) {
    j["reference_classes"] = c.reference_class;
    j["loo_scores"] = c.loo_scores;
    if (c.whitening.size() != 0) j["whitening"] = rows(c.whitening);
    if (c.calibration_folds > 0) j["calibration_folds"] = c.calibration_folds;
    if (c.rule != NoveltyRule::NearestClass) j["rule"] = to_string(c.rule);
  } else {
    j["loo_scores"] = c.loo_scores.front();
  }
  return j;
}

NoveltyCalibration novelty_from_json(const json& j, Eigen::Index n_features, int n_classes, std::int64_t version) {
  if (!j.is_object()) invalid("payload.novelty is not an object");
  NoveltyCalibration c;
  c.per_class = version >= 4;
  const bool whitened = version >= 5, cross_validated = version >= 6, with_rule = version >= 7;
  if (with_rule)
    refuse_unknown_keys(j, {"k", "quantile", "reference", "reference_classes", "loo_scores", "whitening", "calibration_folds", "rule"},
                        "payload.novelty");
  else if (cross_validated)
    refuse_unknown_keys(j, {"k", "quantile", "reference", "reference_classes", "loo_scores", "whitening", "calibration_folds"},
                        "payload.novelty");
  else if (whitened)
    refuse_unknown_keys(j, {"k", "quantile", "reference", "reference_classes", "loo_scores", "whitening"}, "payload.novelty");
  else if (c.per_class)
    refuse_unknown_keys(j, {"k", "quantile", "reference", "reference_classes", "loo_scores"}, "payload.novelty");
  else
    refuse_unknown_keys(j, {"k", "quantile", "reference", "loo_scores"}, "payload.novelty");
  c.k = static_cast<int>(integer(j, "k", "novelty"));
  c.quantile = num(j, "quantile", "novelty");
  c.reference = matrix(field(j, "reference", "novelty"), n_features, "novelty.reference");
  if (c.per_class) {
    c.reference_class = ints(field(j, "reference_classes", "novelty"), "novelty.reference_classes");
    const json& lists = field(j, "loo_scores", "novelty");
    if (!lists.is_array()) invalid("novelty.loo_scores is not an array (one list per class)");
    for (const auto& l : lists) c.loo_scores.push_back(numbers(l, "novelty.loo_scores[]"));
    if (with_rule && j.contains("rule")) {
      const std::string rule = str(j, "rule", "novelty");
      if (rule == to_string(NoveltyRule::PredictedClass)) c.rule = NoveltyRule::PredictedClass;
      else if (rule == to_string(NoveltyRule::MedianScale) && version >= 8) c.rule = NoveltyRule::MedianScale;
      else if (rule == to_string(NoveltyRule::MedianScale))
        throw InvalidInputError("model_version", "payload.novelty.rule 'median_scale' needs format_version 8, the file says " + std::to_string(version));
      else if (rule != to_string(NoveltyRule::NearestClass)) invalid("novelty.rule '" + rule + "' is unknown");
    }
    // Format 7 writes calibration_folds only for cross-validated scores.
    if (cross_validated && (!with_rule || j.contains("calibration_folds"))) {
      const std::int64_t folds = integer(j, "calibration_folds", "novelty");
      if (folds < 2 || folds > c.reference.rows())
        invalid("novelty.calibration_folds = " + std::to_string(folds) + " must be in 2.." + std::to_string(c.reference.rows()));
      c.calibration_folds = static_cast<int>(folds);
    }
    // Format 6 writes whitening only for a whitened figure; format 5 always had it.
    if (whitened && (!cross_validated || j.contains("whitening"))) {
      c.whitening = matrix(field(j, "whitening", "novelty"), n_features, "novelty.whitening");
      if (c.whitening.rows() != n_features)
        invalid("novelty.whitening has " + std::to_string(c.whitening.rows()) + " rows for " + std::to_string(n_features) + " features");
    }
  } else {
    c.reference_class.assign(static_cast<std::size_t>(c.reference.rows()), 0);
    c.loo_scores.push_back(numbers(field(j, "loo_scores", "novelty"), "novelty.loo_scores"));
  }
  validate_novelty(c, n_features, n_classes);
  return c;
}

json payload_of(const ClassifierModel::State& s) {
  json p = payload_without_novelty(s);
  if (s.novelty) p["novelty"] = novelty_to_json(*s.novelty);
  return p;
}

json payload_without_novelty(const ClassifierModel::State& s) {
  const SvmModelData& svm = s.svm.data();
  const TrainingSummary& t = s.summary;
  return {{"name", s.name},
          {"version", s.version},
          {"classes", s.classes},
          {"recipe", recipe_to_json(s.recipe)},
          {"scaler", {{"mean", to_array(s.scaler.mean)}, {"scale", to_array(s.scaler.scale)}}},
          {"svm",
           {{"type", "c_svc"}, {"kernel", "rbf"}, {"C", svm.C}, {"gamma", svm.gamma}, {"n_features", svm.n_features},
            {"n_classes", svm.n_classes}, {"labels", svm.labels}, {"n_sv", svm.n_sv},
            {"support_vectors", rows(svm.support_vectors)}, {"sv_coef", rows(svm.sv_coef)}, {"rho", svm.rho},
            {"prob_a", svm.prob_a}, {"prob_b", svm.prob_b}}},
          {"training",
           {{"dataset_sha256", t.dataset_sha256}, {"trained_at", t.trained_at}, {"samples", t.samples},
            {"best_c", t.best_c}, {"best_gamma", t.best_gamma}, {"grid_score", t.grid_score},
            {"test_accuracy", t.test_accuracy}, {"nested_cv_mean", t.nested_cv_mean},
            {"nested_cv_std", t.nested_cv_std}, {"notes", t.notes},
            {"class_spectra", class_spectra_to_json(t.class_spectra)}}}};
}

std::shared_ptr<ClassifierModel::State> state_from_payload(const json& p, std::int64_t format_version) {
  if (!p.is_object()) invalid("payload is not an object");
  refuse_unknown_keys(p, {"name", "version", "classes", "recipe", "scaler", "svm", "training", "novelty"}, "payload");
  // SVM first: the State owns it by value.
  const json& sj = field(p, "svm", "payload");
  refuse_unknown_keys(sj,
                      {"type", "kernel", "C", "gamma", "n_features", "n_classes", "labels", "n_sv", "support_vectors",
                       "sv_coef", "rho", "prob_a", "prob_b"},
                      "payload.svm");
  if (str(sj, "type", "svm") != "c_svc" || str(sj, "kernel", "svm") != "rbf")
    invalid("only an RBF C-SVM is supported (svm.type c_svc, svm.kernel rbf)");
  SvmModelData svm;
  svm.C = num(sj, "C", "svm");
  svm.gamma = num(sj, "gamma", "svm");
  svm.n_features = static_cast<int>(integer(sj, "n_features", "svm"));
  svm.n_classes = static_cast<int>(integer(sj, "n_classes", "svm"));
  if (svm.n_features < 1 || svm.n_features > 100000 || svm.n_classes < 2 || svm.n_classes > 10000)
    invalid("svm.n_features / svm.n_classes out of range");
  svm.labels = ints(field(sj, "labels", "svm"), "svm.labels");
  svm.n_sv = ints(field(sj, "n_sv", "svm"), "svm.n_sv");
  svm.support_vectors = matrix(field(sj, "support_vectors", "svm"), svm.n_features, "svm.support_vectors");
  const json& coef = field(sj, "sv_coef", "svm");
  svm.sv_coef = matrix(coef, svm.support_vectors.rows(), "svm.sv_coef");
  svm.rho = numbers(field(sj, "rho", "svm"), "svm.rho");
  svm.prob_a = numbers(field(sj, "prob_a", "svm"), "svm.prob_a");
  svm.prob_b = numbers(field(sj, "prob_b", "svm"), "svm.prob_b");
  const Eigen::Index svm_features = svm.n_features;
  auto s = std::make_shared<ClassifierModel::State>(SvmEngine(std::move(svm)));

  s->name = str(p, "name", "payload");
  s->version = str(p, "version", "payload");
  const json& classes = field(p, "classes", "payload");
  if (!classes.is_array()) invalid("payload.classes is not an array");
  for (const auto& c : classes) {
    if (!c.is_string()) invalid("payload.classes contains a non-string");
    s->classes.push_back(c.get<std::string>());
  }
  try {
    s->recipe = recipe_from_json(field(p, "recipe", "payload"));
  } catch (const InvalidInputError& e) {
    if (e.code() == "model_invalid" || e.code() == "model_version") throw;
    invalid(e.what());
  }
  const json& sc = field(p, "scaler", "payload");
  refuse_unknown_keys(sc, {"mean", "scale"}, "payload.scaler");
  const std::vector<double> mean = numbers(field(sc, "mean", "scaler"), "scaler.mean");
  const std::vector<double> scale = numbers(field(sc, "scale", "scaler"), "scaler.scale");
  s->scaler.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  s->scaler.scale = Eigen::Map<const Eigen::VectorXd>(scale.data(), static_cast<Eigen::Index>(scale.size()));
  const json& t = field(p, "training", "payload");
  refuse_unknown_keys(t,
                      {"dataset_sha256", "trained_at", "samples", "best_c", "best_gamma", "grid_score", "test_accuracy",
                       "nested_cv_mean", "nested_cv_std", "notes", "class_spectra"},
                      "payload.training");
  s->summary.dataset_sha256 = str(t, "dataset_sha256", "training");
  s->summary.trained_at = str(t, "trained_at", "training");
  s->summary.samples = integer(t, "samples", "training");
  s->summary.best_c = num(t, "best_c", "training");
  s->summary.best_gamma = num(t, "best_gamma", "training");
  s->summary.grid_score = num(t, "grid_score", "training");
  s->summary.test_accuracy = num(t, "test_accuracy", "training");
  s->summary.nested_cv_mean = num(t, "nested_cv_mean", "training");
  s->summary.nested_cv_std = num(t, "nested_cv_std", "training");
  s->summary.notes = str(t, "notes", "training");
  s->summary.class_spectra = class_spectra_from_json(t);
  if (p.contains("novelty"))
    s->novelty = novelty_from_json(p.at("novelty"), svm_features, s->svm.data().n_classes, format_version);
  return s;
}

json document_of(const ClassifierModel::State& s) {
  json payload = payload_of(s);
  const std::string seal = Sha256::hex(payload.dump());
  // The oldest version that holds what the file has (3: the one-set novelty block, 4: the per-class one, 5: the
  // whitened per-class one, 6: cross-validated calibration scores), so
  // readers of older versions refuse it by number and a model without novelty stays readable by version 2.
  const int version = !s.novelty                        ? 2
                      : !s.novelty->per_class            ? 3
                      : s.novelty->rule == NoveltyRule::MedianScale ? 8
                      : s.novelty->rule != NoveltyRule::NearestClass ? 7
                      : s.novelty->calibration_folds > 0 ? 6
                      : s.novelty->whitening.size() == 0 ? 4
                                                         : 5;
  return {{"format", kFormatName}, {"format_version", version}, {"payload", std::move(payload)},
          {"payload_sha256", seal}};
}

}  // namespace

std::shared_ptr<const ClassifierModel::State> finalize_state(std::shared_ptr<ClassifierModel::State> s) {
  const int k = s->svm.data().n_classes;
  if (static_cast<int>(s->classes.size()) != k)
    invalid(std::to_string(s->classes.size()) + " class names for an SVM with " + std::to_string(k) + " classes");
  for (std::size_t i = 0; i < s->classes.size(); ++i) {
    if (s->classes[i].empty()) invalid("empty class name");
    for (std::size_t j = 0; j < i; ++j)
      if (s->classes[i] == s->classes[j]) invalid("duplicate class name '" + s->classes[i] + "'");
  }
  try {
    validate_feature_spec(s->recipe.features);
    validate_recipe(s->recipe, "model_invalid");
  } catch (const InvalidInputError& e) {
    invalid(e.what());
  }
  const auto d = static_cast<Eigen::Index>(feature_names(s->recipe.features).size());
  if (s->scaler.mean.size() != d || s->scaler.scale.size() != d)
    invalid("the scaler has " + std::to_string(s->scaler.mean.size()) + "/" + std::to_string(s->scaler.scale.size()) +
            " entries for " + std::to_string(d) + " features");
  if (s->svm.data().n_features != d)
    invalid("the SVM has " + std::to_string(s->svm.data().n_features) + " features, the pipeline makes " +
            std::to_string(d));
  if (!s->scaler.mean.allFinite() || !s->scaler.scale.allFinite() || !(s->scaler.scale.array() > 0).all())
    invalid("the scaler has non-finite or non-positive entries");
  s->payload_sha256 = Sha256::hex(payload_of(*s).dump());
  return s;
}

std::string descriptor_recipe_json_text(const DescriptorRecipe& recipe) { return recipe_to_json(recipe).dump(); }

nlohmann::json recipe_to_json(const DescriptorRecipe& r) {
  json out = json::object();
  const int version = recipe_version_of(r);
  SettingsWriter writer{out, version};
  visit_recipe(writer, r);
  out["recipe_version"] = version;
  out["features"]["names"] = feature_names(r.features);  // for readers of the file; checked on load
  return out;
}

nlohmann::json class_spectra_to_json(const std::vector<ClassSpectrum>& spectra) {
  json out = json::array();
  for (const auto& c : spectra)
    out.push_back({{"label", c.label}, {"count", c.count}, {"log_xi_mean", c.log_xi_mean}, {"log_xi_std", c.log_xi_std}});
  return out;
}

std::string ClassifierModel::to_json_text() const { return document_of(*state_).dump(1) + "\n"; }

void ClassifierModel::save(const std::filesystem::path& path) const {
  const std::string text = to_json_text();
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("write_failed", "cannot write the model file " + tmp.string());
    out << text;
    if (!out.flush()) throw IoError("write_failed", "cannot write the model file " + tmp.string());
  }
  std::filesystem::rename(tmp, path);  // never leave a half-written model under the real name
}

ClassifierModel ClassifierModel::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInputError("model_invalid", "cannot open the model file " + path.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  try {
    return from_json_text(ss.str());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(e.code(), path.string() + ": " + e.what(), e.details());
  }
}

ClassifierModel ClassifierModel::from_json_text(const std::string& text) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    invalid(std::string("not valid JSON (truncated or corrupted?): ") + e.what());
  }
  if (!doc.is_object() || !doc.contains("format") || doc["format"] != kFormatName)
    invalid("not a WISH classifier (\"format\" must be \"" + std::string(kFormatName) + "\")");
  if (!doc.contains("format_version") || !doc["format_version"].is_number_integer())
    invalid("missing format_version");
  const auto version = doc["format_version"].get<std::int64_t>();
  if (version < 1 || version > kFormatVersion)
    throw InvalidInputError("model_version",
                            "model file format version " + std::to_string(version) + " is not supported (this build reads versions 1 to " +
                                std::to_string(kFormatVersion) + ")",
                            {{"version", version}, {"supported", std::int64_t{kFormatVersion}}});
  refuse_unknown_keys(doc, {"format", "format_version", "payload", "payload_sha256"}, "document");
  const json& payload = field(doc, "payload", "document");
  if (version < 3 && payload.is_object() && payload.contains("novelty"))
    invalid("payload.novelty needs format_version 3, the file says " + std::to_string(version));
  const std::string seal = str(doc, "payload_sha256", "document");
  const std::string actual = Sha256::hex(payload.dump());
  if (seal != actual)
    invalid("payload_sha256 does not match the content: the file was edited or corrupted (stored " + seal.substr(0, 16) +
            "..., computed " + actual.substr(0, 16) + "...)");
  try {
    // The seal covers the payload as stored; a migrated model is re-sealed over its new payload by finalize_state.
    return ClassifierModel(finalize_state(state_from_payload(version == 1 ? migrate_v1_payload(payload) : payload, version)));
  } catch (const InvalidInputError& e) {
    if (e.code() == "model_invalid" || e.code() == "model_version") throw;
    invalid(e.what());
  } catch (const nlohmann::json::exception& e) {
    invalid(e.what());
  }
}

}  // namespace wish
