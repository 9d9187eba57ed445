// Tests coordinator/dispatch/hello_check.cpp: a Hello of another protocol or build is refused with the reason
// counted and told, and a welcomed one's name and threads are kept within bounds.
#include "coordinator/dispatch/hello_check.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

wire::Hello hello(uint32_t version, uint64_t fingerprint) {
  wire::Hello h;
  h.set_protocol_version(version);
  h.set_fingerprint_digest(fingerprint);
  return h;
}

TEST(HelloCheck, AnotherProtocolOrBuildIsRefusedSayingWhichAndAnyBuildPassesWithoutADigest) {
  EXPECT_FALSE(hello_refusal(hello(wire::PROTOCOL_VERSION, 0xab), 0xab));
  EXPECT_FALSE(hello_refusal(hello(wire::PROTOCOL_VERSION, 0xab), 0));
  const std::optional<HelloRefusal> version = hello_refusal(hello(wire::PROTOCOL_VERSION + 1, 0xab), 0xab);
  ASSERT_TRUE(version);
  EXPECT_EQ(version->reason, DropReason::kWrongVersion);
  EXPECT_NE(version->why.find("the coordinator speaks " + std::to_string(wire::PROTOCOL_VERSION)), std::string::npos);
  const std::optional<HelloRefusal> build = hello_refusal(hello(wire::PROTOCOL_VERSION, 0xcd), 0xab);
  ASSERT_TRUE(build);
  EXPECT_EQ(build->reason, DropReason::kWrongFingerprint);
  EXPECT_NE(build->why.find("compare --fingerprint"), std::string::npos) << build->why;
}

TEST(HelloCheck, AWorkersViewKeepsItsNameToTwoHundredBytesAndItsThreadsWithinBounds) {
  wire::Hello h = hello(wire::PROTOCOL_VERSION, 7);
  h.set_name(std::string(300, 'n'));
  h.set_threads(0);
  WorkerView view = view_of_hello("id", h);
  EXPECT_EQ(view.id, "id");
  EXPECT_EQ(view.name.size(), 200u);
  EXPECT_EQ(view.threads, 1);
  EXPECT_EQ(view.fingerprint_digest, 7u);
  h.set_threads(100000);
  EXPECT_EQ(view_of_hello("id", h).threads, 4096);
}

}  // namespace
}  // namespace poet
