// The cancel registry at the end of the shutdown grace period (cancel_registry.hpp).
#include "server/cancel_registry.hpp"

#include <atomic>
#include <memory>

#include <gtest/gtest.h>

namespace wish::server {
namespace {

TEST(CancelRegistry, CancelAllCancelsWhatIsRegistered) {
  CancelRegistry registry;
  auto flag = std::make_shared<std::atomic<bool>>(false);
  {
    CancelRegistry::Registration registered(registry, flag);
    EXPECT_EQ(registry.size(), 1u);
    EXPECT_FALSE(flag->load());
    registry.cancel_all();
    EXPECT_TRUE(flag->load());
  }
  EXPECT_EQ(registry.size(), 0u);
}

// A request that was between its admission and its registration when the grace ran out would otherwise compute to
// its end and hold up the exit.
TEST(CancelRegistry, CancelAllAlsoCancelsLaterRegistrations) {
  CancelRegistry registry;
  registry.cancel_all();
  auto later = std::make_shared<std::atomic<bool>>(false);
  CancelRegistry::Registration registered(registry, later);
  EXPECT_TRUE(later->load());
}

}  // namespace
}  // namespace wish::server
