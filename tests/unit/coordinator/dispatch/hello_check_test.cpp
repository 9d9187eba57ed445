// Tests coordinator/dispatch/hello_check.cpp: a Hello of another protocol, arithmetic or build is refused with the
// reason counted and told (the arithmetic parts that differ named), and a welcomed one's name and threads are kept
// within bounds.
#include "coordinator/dispatch/hello_check.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

constexpr char kOurParts[] = "math 00000000000000a1, box2d 00000000000000b1, walker 00000000000000c1";

wire::Hello hello(uint32_t version, uint64_t fingerprint, uint64_t arithmetic = 0xa7,
                  const std::string& parts = kOurParts) {
  wire::Hello h;
  h.set_protocol_version(version);
  h.set_fingerprint_digest(fingerprint);
  h.set_arithmetic_digest(arithmetic);
  h.set_arithmetic(parts);
  return h;
}

HelloExpectation expecting(uint64_t fingerprint, uint64_t arithmetic = 0xa7) {
  return {fingerprint, arithmetic, kOurParts};
}

TEST(HelloCheck, AnotherProtocolOrBuildIsRefusedSayingWhichAndAnyBuildPassesWithoutADigest) {
  EXPECT_FALSE(hello_refusal(hello(wire::PROTOCOL_VERSION, 0xab), expecting(0xab)));
  EXPECT_FALSE(hello_refusal(hello(wire::PROTOCOL_VERSION, 0xab), expecting(0, 0)));
  const std::optional<HelloRefusal> version = hello_refusal(hello(wire::PROTOCOL_VERSION + 1, 0xab), expecting(0xab));
  ASSERT_TRUE(version);
  EXPECT_EQ(version->reason, DropReason::kWrongVersion);
  EXPECT_NE(version->why.find("the coordinator speaks " + std::to_string(wire::PROTOCOL_VERSION)), std::string::npos);
  const std::optional<HelloRefusal> build = hello_refusal(hello(wire::PROTOCOL_VERSION, 0xcd), expecting(0xab));
  ASSERT_TRUE(build);
  EXPECT_EQ(build->reason, DropReason::kWrongFingerprint);
  EXPECT_NE(build->why.find("compare --fingerprint"), std::string::npos) << build->why;
}

TEST(HelloCheck, AMachineThatComputesDifferentlyIsToldSoNamingThePartsThatDiffer) {
  const std::string their_parts = "math 00000000000000a2, box2d 00000000000000b1, walker 00000000000000c2";
  // the arithmetic is checked before the build: a fingerprint that differs too is not what the worker is told
  const std::optional<HelloRefusal> refusal =
      hello_refusal(hello(wire::PROTOCOL_VERSION, 0xcd, 0xa8, their_parts), expecting(0xab));
  ASSERT_TRUE(refusal);
  EXPECT_EQ(refusal->reason, DropReason::kWrongArithmetic);
  EXPECT_EQ(refusal->why,
            "this machine computes differently from the coordinator: arithmetic digest 00000000000000a8, the "
            "coordinator's 00000000000000a7 (math, walker differ): its results would differ from the coordinator's "
            "for the same job (compare the arithmetic line of --fingerprint on both machines)");
  // a Hello without the digest (an older worker) or with parts that are not of the form: no parts named
  wire::Hello old = hello(wire::PROTOCOL_VERSION, 0xab);
  old.clear_arithmetic_digest();
  old.clear_arithmetic();
  const std::optional<HelloRefusal> missing = hello_refusal(old, expecting(0xab));
  ASSERT_TRUE(missing);
  EXPECT_NE(missing->why.find("arithmetic digest missing, the coordinator's 00000000000000a7: "), std::string::npos)
      << missing->why;
  for (const std::string& garbage : {std::string(500, 'x'), std::string("math \x01\x02"), std::string("math"),
                                     std::string("math 00000000000000a2, walker"), std::string(", , ")}) {
    const std::optional<HelloRefusal> odd =
        hello_refusal(hello(wire::PROTOCOL_VERSION, 0xab, 0xa8, garbage), expecting(0xab));
    ASSERT_TRUE(odd);
    EXPECT_EQ(odd->why.find(" differ)"), std::string::npos) << odd->why;
  }
}

TEST(HelloCheck, AWorkersViewKeepsItsNameToTwoHundredBytesAndItsThreadsWithinBounds) {
  wire::Hello h = hello(wire::PROTOCOL_VERSION, 7, 9);
  h.set_name(std::string(300, 'n'));
  h.set_threads(0);
  WorkerFacts view = facts_of_hello("id", h);
  EXPECT_EQ(view.id, "id");
  EXPECT_EQ(view.name.size(), 200u);
  EXPECT_EQ(view.threads, 1);
  EXPECT_EQ(view.fingerprint_digest, 7u);
  EXPECT_EQ(view.arithmetic_digest, 9u);
  h.set_threads(100000);
  EXPECT_EQ(facts_of_hello("id", h).threads, 4096);
}

}  // namespace
}  // namespace poet
