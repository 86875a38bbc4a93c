#pragma once
// Synthetic labelled feature vectors for the classifier tests: no meshes, no maps, milliseconds to make.

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/classify/global_descriptors.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/training/training.hpp"

namespace wish::testing {

// `per_class` samples of `classes` classes; xi(l) ~ class-dependent decay with multiplicative noise, so the
// classes overlap a little (accuracy well below 1 at some grid cells, above chance at the best one).
inline std::vector<TrainingSample> synthetic_samples(int classes, int per_class, std::uint64_t seed, int lmax = 8,
                                                     double noise = 0.35) {
  std::mt19937_64 rng(seed);
  auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  auto normal = [&] {  // Box-Muller on our own uniforms: portable across standard libraries
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  };
  std::vector<TrainingSample> out;
  for (int i = 0; i < per_class; ++i)
    for (int c = 0; c < classes; ++c) {
      TrainingSample s;
      s.label = "class_" + std::string(1, static_cast<char>('a' + c));
      s.id = s.label + "_" + std::to_string(i);
      s.features.invariants.resize(lmax + 1);
      const double size = 1.0 + 0.3 * c;
      for (int l = 0; l <= lmax; ++l)
        s.features.invariants(l) = size * std::pow(1.0 + l, -(1.5 + 0.4 * c * (l % 2 ? 1.0 : 0.6))) * std::exp(noise * normal());
      s.features.global.resize(kGlobalCount);
      for (int g = 0; g < kGlobalCount; ++g) s.features.global(g) = 1.0 + 0.2 * c * (g % 3 == 0) + 0.15 * normal();
      s.features.global(kGlobalArea) = std::abs(s.features.global(kGlobalArea)) + 0.5;
      out.push_back(std::move(s));
    }
  return out;
}

// A quick training configuration (small grid, few splits) for tests.
inline TrainOptions quick_train_options(std::uint64_t seed = 7) {
  TrainOptions o;
  o.seed = seed;
  o.recipe.features.l_min = 1;
  o.recipe.features.l_max = 6;
  o.recipe.features.log_transform = true;
  o.recipe.sh.lmax = 8;
  o.grid.Cs = decade_grid(-1, 3);
  o.grid.gammas = decade_grid(-3, 1);
  o.grid.jobs = 2;
  o.grid_splits = 4;
  o.nested_repeats = 1;
  o.nested_outer_folds = 3;
  o.nested_inner_splits = 3;
  o.trained_at = "2024-01-01T00:00:00Z";
  return o;
}

// synthetic_samples as a z-scored feature matrix (log xi(1..6)) with class indices: what a grid search sees.
struct StandardizedData {
  Eigen::MatrixXd X;
  std::vector<int> y;
};

inline StandardizedData standardized(int classes, int per_class, std::uint64_t seed, double noise = 0.35) {
  const auto samples = synthetic_samples(classes, per_class, seed, 8, noise);
  FeatureSpec spec;
  spec.l_max = 6;
  spec.log_transform = true;
  StandardizedData d;
  std::vector<std::string> names;
  build_feature_matrix(samples, spec, d.X, d.y, names);
  d.X = StandardScaler::fit(d.X).transform(d.X);
  return d;
}

}  // namespace wish::testing
