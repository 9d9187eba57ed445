// Tests common/plumbing/host_port.cpp: HOST:PORT and [IPv6]:PORT read, anything else refused.

#include "common/plumbing/host_port.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(HostPort, AddressesAreHostAndPort) {
  Expected<HostPort> v4 = parse_host_port("127.0.0.1:8580");
  ASSERT_TRUE(v4);
  EXPECT_EQ(v4->host, "127.0.0.1");
  EXPECT_EQ(v4->port, 8580);
  Expected<HostPort> v6 = parse_host_port("[::1]:0");
  ASSERT_TRUE(v6);
  EXPECT_EQ(v6->host, "::1");
  EXPECT_FALSE(parse_host_port("::1:80"));
  EXPECT_FALSE(parse_host_port("host:65536"));
  EXPECT_FALSE(parse_host_port(":80"));
}

}  // namespace
}  // namespace poet
