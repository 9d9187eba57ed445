#include "common/program/build_fingerprint.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "common/text/text_format.h"
#include "simulation/arithmetic_probe.h"
#include "simulation/rng.h"

namespace poet {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The value after "key: " on the line that starts with it, or "" when there is none.
std::string value_of(const std::string& text, const std::string& key) {
  for (const std::string& line : lines(text))
    if (line.starts_with(key + ": ")) return line.substr(key.size() + 2);
  return "";
}

TEST(BuildFingerprint, NamesEveryPartOfTheBuild) {
  const std::string text = build_fingerprint();
  EXPECT_NE(text.find("box2d: 2.4."), std::string::npos) << text;
  EXPECT_NE(value_of(text, "float mode").find("-ffp-contract=off"), std::string::npos) << text;
  EXPECT_NE(value_of(text, "float mode").find("-fno-fast-math"), std::string::npos) << text;
  EXPECT_FALSE(value_of(text, "poet").empty()) << text;
  EXPECT_FALSE(value_of(text, "compiler").empty()) << text;
  EXPECT_FALSE(value_of(text, "target").empty()) << text;
  EXPECT_EQ(value_of(text, "walker").size(), 16u) << text;
  EXPECT_EQ(value_of(text, "arithmetic"), hex_text(arithmetic_digest()) + " (" + arithmetic_text() + ")") << text;
}

TEST(BuildFingerprint, TheArithmeticIsTheProbesAndItsPartsAreNamed) {
  const ArithmeticProbe probe = probe_arithmetic();
  EXPECT_EQ(arithmetic_digest(), probe.digest());
  EXPECT_EQ(arithmetic_text(),
            "math " + hex_text(probe.math) + ", box2d " + hex_text(probe.box2d) + ", walker " + hex_text(probe.walker));
}

// The digest covers what decides the numbers, not the flags that say how this ISA gets them: a worker on another
// processor that computes alike must share it. Here: the digest is the same with the last two lines removed.
TEST(BuildFingerprint, TheDigestCoversTheLinesUpToTheArithmeticOnly) {
  const std::vector<std::string> all = lines(build_fingerprint());
  ASSERT_EQ(all.size(), 8u);
  EXPECT_TRUE(all[4].starts_with("arithmetic: "));
  EXPECT_TRUE(all[5].starts_with("float mode: "));
  EXPECT_TRUE(all[6].starts_with("target: "));
  std::string compared;
  for (size_t i = 0; i < 5; ++i) compared += all[i] + "\n";
  EXPECT_EQ(build_fingerprint_digest(), mix64(hash_name(compared)));
}

TEST(BuildFingerprint, EveryLineIsKeyColonValueEndingInTheDigest) {
  const std::string text = build_fingerprint();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const std::vector<std::string> all = lines(text);
  ASSERT_EQ(all.size(), 8u) << text;
  for (const std::string& line : all) EXPECT_NE(line.find(": "), std::string::npos) << line;
  EXPECT_TRUE(all.back().starts_with("digest: ")) << text;
}

TEST(BuildFingerprint, DigestLineMatchesTheNumber) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(build_fingerprint_digest()));
  EXPECT_EQ(value_of(build_fingerprint(), "digest"), hex);
  EXPECT_NE(build_fingerprint_line().find(hex), std::string::npos) << build_fingerprint_line();
  EXPECT_NE(build_fingerprint_line().find("-ffp-contract=off"), std::string::npos) << build_fingerprint_line();
}

TEST(BuildFingerprint, IsStableAcrossCalls) {
  const std::string first = build_fingerprint();
  EXPECT_EQ(build_fingerprint(), first);
  EXPECT_EQ(build_fingerprint_digest(), build_fingerprint_digest());
}

}  // namespace
}  // namespace poet
