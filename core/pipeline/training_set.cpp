#include "core/pipeline/training_set.hpp"

#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/common/errors.hpp"

namespace wish {

std::string read_input_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInputError("file_not_found", "cannot open '" + path + "'", {{"file", path}});
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {

// The recipe's check on a described mesh: a sample, or a thrown WishError("off_recipe") under the refuse policy.
TrainingSample sample_of(const PipelineResult& r, const DescriptorRecipe& recipe, const std::string& id,
                         const std::string& label) {
  const RecipeConformance conformance = check_recipe(recipe, r.map);
  enforce_recipe_policy(recipe, conformance, "being trained");
  TrainingSample s;
  s.off_recipe = !conformance.match;
  s.id = id;
  s.label = label;
  s.features.invariants = r.sh.invariants;
  s.features.global = r.features.global;
  return s;
}

ItemDescription describe_mesh_item(const DatasetItem& item, const std::string& bytes, const DescriptorRecipe& recipe,
                                   PipelineOptions po) {
  const auto dot = item.path.find_last_of('.');
  if (dot != std::string::npos) po.read.hint = format_from_name(item.path.substr(dot));
  const PipelineResult r = describe_mesh_bytes(bytes, po);
  ItemDescription d;
  d.samples.push_back(sample_of(r, recipe, item.path, item.label));
  std::ostringstream st;
  st << "ok (" << std::fixed << std::setprecision(2) << r.timings.total << " s, " << to_string(r.map.method_used) << ")";
  if (d.samples.back().off_recipe) st << " OFF-RECIPE, kept (accept_flagged)";
  d.status = st.str();
  return d;
}

}  // namespace

ItemDescriber recipe_describer(const DescriptorRecipe& recipe, const TrainingDescribeOptions& options) {
  PipelineOptions po = options_for_recipe(recipe, options.base);
  po.compute_global_features = true;  // for the feature family comparison
  return [recipe, po, options](const DatasetItem& item) {
    const std::string bytes = read_input_file(item.path);
    return describe_mesh_item(item, bytes, recipe, po);
  };
}

}  // namespace wish
