// ServerConfig::finalize (server/config.hpp) on the Lmax limit: the service's max_lmax must lie within core's range
// (issue 37 item 5: core owns the bound), so a limit the SH fit would refuse is a configuration error at start, and
// the message names core's bound.
#include "server/config.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/sh/sh_lmax_range.hpp"

namespace wish::server {
namespace {

ServerConfig config_with_max_lmax(int max_lmax) {
  ServerConfig c;
  c.models_dir = "models";
  c.workers = 1;
  c.max_lmax = max_lmax;
  return c;
}

// The message of the InvalidInputError("bad_config") finalize throws; "" when it accepts the configuration.
std::string refusal(ServerConfig c) {
  try {
    c.finalize();
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "bad_config");
    return e.what();
  }
  return "";
}

TEST(ServerConfig, MaxLmaxAboveTheFitsBoundIsRefusedNamingIt) {
  const std::string message = refusal(config_with_max_lmax(kShMaxFitLmax + 1));
  ASSERT_FALSE(message.empty()) << "max_lmax " << kShMaxFitLmax + 1 << " accepted above the SH fit's limit";
  EXPECT_NE(message.find(std::to_string(kShMaxFitLmax)), std::string::npos) << message;
  EXPECT_NE(message.find("SH fit"), std::string::npos) << message;
  EXPECT_FALSE(refusal(config_with_max_lmax(200)).empty()) << "the old bound 200 must not come back";
}

TEST(ServerConfig, MaxLmaxWithinCoresRangeIsAccepted) {
  EXPECT_EQ(refusal(config_with_max_lmax(kShMaxFitLmax)), "");
  EXPECT_EQ(refusal(config_with_max_lmax(kMinFeatureLmax)), "");
  EXPECT_EQ(refusal(config_with_max_lmax(ServerConfig{}.max_lmax)), "") << "the default must be within core's range";
}

TEST(ServerConfig, MaxLmaxBelowTheFeaturesMinimumIsRefused) {
  EXPECT_FALSE(refusal(config_with_max_lmax(kMinFeatureLmax - 1)).empty());
}

}  // namespace
}  // namespace wish::server
