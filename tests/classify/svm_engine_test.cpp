#include <gtest/gtest.h>

#include <numeric>
#include <thread>

#include "core/classify/standard_scaler.hpp"
#include "core/classify/svm_engine.hpp"
#include "core/common/errors.hpp"
#include "core/training/training.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

void matrix_of(const std::vector<TrainingSample>& s, Eigen::MatrixXd& X, std::vector<int>& y) {
  FeatureSpec spec;
  spec.l_max = 6;
  spec.log_transform = true;
  std::vector<std::string> classes;
  build_feature_matrix(s, spec, X, y, classes);
  X = StandardScaler::fit(X).transform(X);
}

TEST(SvmEngine, TrainsAndPredictsWithProbabilities) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  matrix_of(testing::synthetic_samples(3, 20, 1), X, y);
  SvmParams p;
  p.C = 10;
  p.gamma = 0.1;
  const SvmEngine svm = SvmEngine::train(X, y, p, 5);
  ASSERT_TRUE(svm.has_probability());
  EXPECT_EQ(svm.data().n_classes, 3);
  int correct = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const SvmOutput out = svm.predict(X.row(i).transpose());
    ASSERT_EQ(out.probability.size(), 3u);
    EXPECT_NEAR(std::accumulate(out.probability.begin(), out.probability.end(), 0.0), 1.0, 1e-9);
    EXPECT_EQ(out.label, svm.predict_label(X.row(i).transpose()));
    correct += out.label == y[static_cast<std::size_t>(i)];
  }
  EXPECT_GT(correct, 40);  // well above chance (20) on the training data
}

TEST(SvmEngine, SameSeedSameModelIncludingCalibration) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  matrix_of(testing::synthetic_samples(3, 15, 2), X, y);
  SvmParams p;
  p.C = 1;
  p.gamma = 0.3;
  // Train concurrently from several threads: the global rand() lock keeps each result seed-determined.
  std::vector<SvmModelData> models(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { models[t] = SvmEngine::train(X, y, p, 99).data(); });
  for (auto& t : threads) t.join();
  for (int t = 1; t < 4; ++t) {
    EXPECT_EQ(models[t].prob_a, models[0].prob_a);
    EXPECT_EQ(models[t].prob_b, models[0].prob_b);
    EXPECT_EQ(models[t].rho, models[0].rho);
  }
}

TEST(SvmEngine, CopiedDataPredictsIdentically) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  matrix_of(testing::synthetic_samples(4, 10, 3), X, y);
  SvmParams p;
  p.C = 100;
  p.gamma = 0.05;
  const SvmEngine a = SvmEngine::train(X, y, p, 1);
  const SvmEngine b(a.data());  // owns its own copy; `a` could go away
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const auto pa = a.predict(X.row(i).transpose()), pb = b.predict(X.row(i).transpose());
    EXPECT_EQ(pa.label, pb.label);
    EXPECT_EQ(pa.decision, pb.decision);
    EXPECT_EQ(pa.probability, pb.probability);
  }
}

TEST(SvmEngine, RefusesInconsistentData) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  matrix_of(testing::synthetic_samples(3, 8, 4), X, y);
  SvmParams p;
  const SvmModelData good = SvmEngine::train(X, y, p, 1).data();
  auto expect_refused = [](SvmModelData d) {
    try {
      SvmEngine e(std::move(d));
      FAIL() << "accepted";
    } catch (const InvalidInputError& e) {
      EXPECT_EQ(e.code(), "model_invalid");
    }
  };
  SvmModelData d = good;
  d.rho.pop_back();
  expect_refused(d);
  d = good;
  d.n_sv[0] += 1;
  expect_refused(d);
  d = good;
  d.labels = {0, 0, 1};
  expect_refused(d);
  d = good;
  d.sv_coef.conservativeResize(d.sv_coef.rows(), d.sv_coef.cols() - 1);
  expect_refused(d);
  d = good;
  d.support_vectors(0, 0) = std::numeric_limits<double>::quiet_NaN();
  expect_refused(d);
  EXPECT_THROW(SvmEngine(good).predict(Eigen::VectorXd::Zero(2)), InvalidInputError);
}

}  // namespace
}  // namespace wish
