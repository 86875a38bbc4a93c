#include <gtest/gtest.h>

#include "core/classify/feature_pipeline.hpp"
#include "core/classify/global_descriptors.hpp"
#include "core/common/errors.hpp"
#include "core/training/descriptor_table.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

TEST(DescriptorTable, RoundTripWithLabelsAndGlobals) {
  auto samples = testing::synthetic_samples(2, 3, 4, 4);
  samples[0].id = "dir with, comma/\"x\".ply";
  const DescriptorTable t = read_descriptor_table(write_descriptor_table(samples));
  ASSERT_EQ(t.samples.size(), samples.size());
  EXPECT_EQ(t.lmax, 4);
  EXPECT_TRUE(t.has_global);
  EXPECT_EQ(t.samples[0].id, samples[0].id);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(t.samples[i].label, samples[i].label);
    EXPECT_EQ(t.samples[i].features.invariants, samples[i].features.invariants);  // 17 digits: exact
    EXPECT_EQ(t.samples[i].features.global, samples[i].features.global);
  }
}

// Issue 38: the spectrum (lb_1..lb_n) and the canonical SH coefficients (csh_<l>_<m>_<axis>, degrees 1..L) round
// trip, and the feature pipeline reads them back for the families that use them.
TEST(DescriptorTable, RoundTripWithSpectrumAndCanonicalCoefficients) {
  auto samples = testing::synthetic_samples(2, 3, 4, 4);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    samples[i].features.laplace_spectrum = Eigen::VectorXd::LinSpaced(5, 2.0 + static_cast<double>(i), 30.0);
    samples[i].features.canonical_sh = Eigen::VectorXd::LinSpaced(3 * 15, -1.0, 1.0 + static_cast<double>(i));  // L = 3
  }
  const std::string text = write_descriptor_table(samples);
  EXPECT_NE(text.find(",lb_5,csh_1_-1_x,"), std::string::npos);
  EXPECT_NE(text.find(",csh_3_3_z\n"), std::string::npos);
  const DescriptorTable t = read_descriptor_table(text);
  ASSERT_EQ(t.samples.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(t.samples[i].features.laplace_spectrum, samples[i].features.laplace_spectrum);
    EXPECT_EQ(t.samples[i].features.canonical_sh, samples[i].features.canonical_sh);
  }
  FeatureSpec spec;
  spec.family = FeatureFamily::All;
  spec.l_min = 2;
  spec.l_max = 3;
  spec.spectrum_count = 4;
  spec.log_transform = false;
  const Eigen::VectorXd x = apply_feature_pipeline(t.samples[1].features, spec);
  // xi(2..3), lb_1..4, csh degrees 2..3 (3 x 12 values from value 9 on), 11 global.
  ASSERT_EQ(x.size(), 2 + 4 + 36 + 11);
  EXPECT_EQ(static_cast<std::size_t>(x.size()), feature_names(spec).size());
  EXPECT_EQ(x(2), samples[1].features.laplace_spectrum(0));
  EXPECT_EQ(x(6), samples[1].features.canonical_sh(9));
  spec.spectrum_count = 6;  // more eigenvalues than the descriptor has
  EXPECT_THROW(apply_feature_pipeline(t.samples[1].features, spec), InvalidInputError);
}

TEST(DescriptorTable, DescribeCsvJoinedWithAManifest) {
  // The layout of `wish describe --csv` (no label, no g_ columns).
  const std::string csv =
      "file,n_vertices,n_faces,map_method,xi_0,xi_1,xi_2\n"
      "/data/a/one.ply,10,16,willmore,1,0.5,0.25\n"
      "/elsewhere/two.ply,10,16,willmore,2,0.4,0.2\n"
      "/data/three.ply,10,16,willmore,3,0.3,0.1\n";
  const auto manifest = read_manifest("path,label\na/one.ply,neuron\ntwo.ply,glia\n", "/data");
  std::map<std::string, std::string> labels(manifest.begin(), manifest.end());
  const DescriptorTable t = read_descriptor_table(csv, labels);
  ASSERT_EQ(t.samples.size(), 2u);
  EXPECT_EQ(t.samples[0].label, "neuron");  // exact path
  EXPECT_EQ(t.samples[1].label, "glia");    // joined on the file name
  EXPECT_FALSE(t.has_global);
  EXPECT_EQ(t.unlabelled, std::vector<std::string>{"/data/three.ply"});  // reported, not silently dropped
}

TEST(DescriptorTable, UnlabelledTableKeepsEveryRowForPrediction) {
  const std::string csv =
      "file,n_vertices,xi_0,xi_1,xi_2\n"
      "one.ply,10,1,0.5,0.25\n"
      "two.ply,10,2,0.4,0.2\n";
  EXPECT_THROW(read_descriptor_table(csv), InvalidInputError);  // training needs labels
  const DescriptorTable t = read_unlabelled_descriptor_table(csv);
  ASSERT_EQ(t.samples.size(), 2u);
  EXPECT_TRUE(t.unlabelled.empty());
  EXPECT_EQ(t.lmax, 2);
  EXPECT_EQ(t.samples[1].id, "two.ply");
  EXPECT_TRUE(t.samples[1].label.empty());
  EXPECT_DOUBLE_EQ(t.samples[1].features.invariants(2), 0.2);
  EXPECT_THROW(read_unlabelled_descriptor_table("file,xi_0\na,x\n"), InvalidInputError);  // still checked
}

TEST(DescriptorTable, ClearErrors) {
  EXPECT_THROW(read_descriptor_table("file,xi_0\na,1\n"), InvalidInputError);           // no labels at all
  EXPECT_THROW(read_descriptor_table("file,label,xi_0,xi_2\na,b,1,2\n"), InvalidInputError);  // xi_1 missing
  EXPECT_THROW(read_descriptor_table("file,label,xi_0\na,b,x\n"), InvalidInputError);    // not a number
  EXPECT_THROW(read_descriptor_table("file,label,xi_0\na,b\n"), InvalidInputError);      // short line
}

}  // namespace
}  // namespace wish
