// The numeric bounds proto/openapi.json states for Lmax are core's (issue 37 item 5: core owns every bound, the
// edges read it): a request's lmax runs from the features' minimum to the SH fit's maximum, and a descriptor in a
// response from the fit's minimum to its maximum. The file is hand-edited, so this test is what keeps it honest when
// a core constant moves.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/classify/feature_pipeline.hpp"
#include "core/sh/sh_lmax_range.hpp"

namespace wish::wire {
namespace {

const std::filesystem::path kContractSource = WISH_TEST_SOURCE_DIR;

nlohmann::json openapi_document() {
  std::ifstream in(kContractSource / "proto" / "openapi.json", std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

TEST(ContractBounds, TheRequestLmaxRangeIsCores) {
  const nlohmann::json schema = openapi_document().at("components").at("parameters").at("lmax").at("schema");
  EXPECT_EQ(schema.at("minimum").get<int>(), kMinFeatureLmax);
  EXPECT_EQ(schema.at("maximum").get<int>(), kShMaxFitLmax);
}

TEST(ContractBounds, TheDescriptorLmaxRangeIsTheFits) {
  const nlohmann::json block = openapi_document().at("components").at("schemas").at("DescriptorBlock").at("properties");
  for (const nlohmann::json* lmax : {&block.at("lmax"), &block.at("options").at("properties").at("lmax")}) {
    EXPECT_EQ(lmax->at("minimum").get<int>(), kShMinFitLmax) << *lmax;
    EXPECT_EQ(lmax->at("maximum").get<int>(), kShMaxFitLmax) << *lmax;
  }
}

}  // namespace
}  // namespace wish::wire
