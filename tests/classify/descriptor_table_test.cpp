#include <gtest/gtest.h>

#include "core/classify/descriptor_table.hpp"
#include "core/classify/global_descriptors.hpp"
#include "core/common/errors.hpp"
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
