// Every enum whose names are parsed back (model files, CLI options, request parameters) round-trips through its
// one table: to_string(x) parses to x, and the names are distinct and never the table's "?" for a missing entry.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/classify/descriptor_recipe.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/sh/sh_descriptor.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish {
namespace {

template <class E, class Parse>
void expect_round_trip(std::initializer_list<E> all, Parse parse) {
  std::set<std::string> names;
  for (E value : all) {
    const std::string name = to_string(value);
    EXPECT_NE(name, "?");
    EXPECT_TRUE(names.insert(name).second) << "duplicate name " << name;
    EXPECT_EQ(parse(name), value) << name;
  }
  EXPECT_THROW((void)parse("no-such-name"), InvalidInputError);
}

TEST(EnumNamesRoundTrip, EveryParsedEnum) {
  expect_round_trip({MapMethod::Willmore, MapMethod::Cmcf, MapMethod::Linear, MapMethod::Progressive}, map_method_from_name);
  expect_round_trip({LinearSolverKind::Cholmod, LinearSolverKind::EigenSimplicial}, linear_solver_from_name);
  expect_round_trip({FitWeighting::Area, FitWeighting::Uniform}, fit_weighting_from_name);
  expect_round_trip({FitSolver::Direct, FitSolver::Banded}, fit_solver_from_name);
  expect_round_trip({GramMethod::Quadrature, GramMethod::Product}, gram_method_from_name);
  expect_round_trip({FeatureFamily::Invariants, FeatureFamily::Global, FeatureFamily::Combined},
                    feature_family_from_name);
  expect_round_trip({ScaleNormalization::None, ScaleNormalization::ByFirstInvariant, ScaleNormalization::ByArea},
                    scale_normalization_from_name);
  expect_round_trip({OffRecipePolicy::Refuse, OffRecipePolicy::AcceptFlagged}, off_recipe_policy_from_name);
  using geometry::LaplacianKind;
  expect_round_trip({LaplacianKind::Extrinsic, LaplacianKind::Mollified, LaplacianKind::IntrinsicDelaunay},
                    [](const std::string& n) { return geometry::laplacian_kind_from_name(n.c_str()); });
}

}  // namespace
}  // namespace wish
