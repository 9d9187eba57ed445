// Tests the descriptor budget of coordinator/status/status_server.cpp (descriptors_needed, fit_listeners): the
// listeners keep their caps when they fit in half of the process's descriptor limit, and shrink, each address's cap
// with them, until they do; the server itself is tested over sockets in tests/integration/status_server_test.cpp.

#include "coordinator/status/status_server.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(FitListenersTest, TheDefaultsFitInTheUsualLimits) {
  for (uint64_t limit : {uint64_t{4096}, uint64_t{524288}, UINT64_MAX}) {
    StatusServerOptions status;
    StatusServerOptions health = health_listener_options();
    EXPECT_FALSE(fit_listeners(limit, status, health)) << limit;
    EXPECT_EQ(status.caps.total, 1024u);
    EXPECT_EQ(status.caps.per_address, 256u);
    EXPECT_EQ(health.caps.total, 256u);
    EXPECT_EQ(health.caps.per_address, 64u);
    EXPECT_LE(descriptors_needed(status) + descriptors_needed(health), limit / 2);
  }
}

TEST(FitListenersTest, ALowLimitShrinksBothIntoItsHalf) {
  for (uint64_t limit : {uint64_t{1024}, uint64_t{2048}, uint64_t{300}}) {
    StatusServerOptions status;
    StatusServerOptions health = health_listener_options();
    EXPECT_TRUE(fit_listeners(limit, status, health)) << limit;
    EXPECT_LE(descriptors_needed(status) + descriptors_needed(health), limit / 2) << limit;
    EXPECT_LT(status.caps.total, 1024u);
    EXPECT_GT(status.caps.total, health.caps.total) << "both by one factor";
    EXPECT_LE(status.caps.per_address, status.caps.total);
    EXPECT_LE(health.caps.per_address, health.caps.total);
  }
  StatusServerOptions status;
  StatusServerOptions health = health_listener_options();
  fit_listeners(1024, status, health);
  EXPECT_EQ(status.caps.total, 297u);
  EXPECT_EQ(status.caps.per_address, 74u);
  EXPECT_EQ(health.caps.total, 74u);
  EXPECT_EQ(health.caps.per_address, 18u);
}

TEST(FitListenersTest, AnAbsurdLimitLeavesOneSlotEach) {
  StatusServerOptions status;
  StatusServerOptions health = health_listener_options();
  EXPECT_TRUE(fit_listeners(0, status, health));
  EXPECT_EQ(status.caps.total, 1u);
  EXPECT_EQ(health.caps.per_address, 1u);
}

}  // namespace
}  // namespace poet
