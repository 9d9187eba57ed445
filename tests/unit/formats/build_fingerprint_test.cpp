#include "formats/build_fingerprint.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

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
}

TEST(BuildFingerprint, EveryLineIsKeyColonValueEndingInTheDigest) {
  const std::string text = build_fingerprint();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const std::vector<std::string> all = lines(text);
  ASSERT_EQ(all.size(), 7u) << text;
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
