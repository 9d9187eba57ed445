// Tests common/formats/policy/policy_file.cpp: exact round trips, an error naming the problem for each kind of hostile
// input, and atomic saving.

#include "common/formats/policy/policy_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scratch_dir.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

// Parameters with the values most likely to lose bits in text: negative zero, subnormals, extremes, thirds.
std::vector<double> tricky_params() {
  RandomStream rng(stream_key(1, "policy_file_test"));
  std::vector<double> p = random_params(rng, 1.0);
  const std::vector<double> specials = {-0.0,      0.1,
                                        1.0 / 3.0, 5e-324,
                                        -DBL_MIN,  DBL_MAX,
                                        -DBL_MAX,  1e22,
                                        1e23,      123456789012345678.0,
                                        2.0,       -1.0000000000000002};
  for (size_t i = 0; i < specials.size(); ++i) p[i * 97] = specials[i];
  return p;
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(std::bit_cast<uint64_t>(a[i]), std::bit_cast<uint64_t>(b[i])) << "parameter " << i << ": " << a[i];
  }
}

// A policy text with the given parameter texts and score text (empty: no score).
std::string policy_text(const std::vector<std::string>& params, const std::string& score = "") {
  std::string text = "[[";
  for (size_t i = 0; i < params.size(); ++i) text += (i ? "," : "") + params[i];
  text += "]";
  if (!score.empty()) text += "," + score;
  return text + "]";
}

std::vector<std::string> zero_texts(size_t n = kParamCount) { return std::vector<std::string>(n, "0"); }

std::vector<std::string> with(size_t index, const std::string& value) {
  std::vector<std::string> t = zero_texts();
  t[index] = value;
  return t;
}

// A fresh empty directory per test, removed afterwards.
class PolicyFileDirTest : public ::testing::Test {
 protected:
  std::vector<fs::path> files() const {
    std::vector<fs::path> out;
    for (const auto& entry : fs::directory_iterator(dir_)) out.push_back(entry.path().filename());
    return out;
  }

  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
};

TEST(PolicyFileTest, TextRoundTripIsExactWithScore) {
  const std::vector<double> p = tricky_params();
  const Expected<PolicyFile> r = parse_policy(policy_json_text(p, 314.38509374999995));
  ASSERT_TRUE(r) << r.error();
  EXPECT_TRUE(r.error().empty());
  expect_same_bits(r->params, p);
  ASSERT_TRUE(r->score.has_value());
  EXPECT_EQ(*r->score, 314.38509374999995);
}

TEST(PolicyFileTest, TextRoundTripIsExactWithoutScore) {
  const std::vector<double> p = tricky_params();
  const std::string text = policy_json_text(p);
  EXPECT_EQ(text.substr(0, 2), "[[");
  const Expected<PolicyFile> r = parse_policy(text);
  ASSERT_TRUE(r) << r.error();
  expect_same_bits(r->params, p);
  EXPECT_FALSE(r->score.has_value());
}

TEST(PolicyFileTest, ParsesTheReferenceLayout) {
  // estool writes one number per line, integers without a decimal point, and a score after the list
  std::vector<std::string> t = zero_texts();
  t[0] = "0.7422";
  t[1] = "-3";
  t[2803] = "-0.1031";
  std::string text = "[\n[\n";
  for (size_t i = 0; i < t.size(); ++i) text += t[i] + (i + 1 < t.size() ? ",\n" : "\n");
  text += "],\n305.64538671875\n]";
  const Expected<PolicyFile> r = parse_policy(text);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->params[0], 0.7422);
  EXPECT_EQ(r->params[1], -3.0);
  EXPECT_EQ(r->params[2803], -0.1031);
  EXPECT_EQ(r->score, 305.64538671875);
}

struct BadCase {
  std::string label;
  std::string text;
  std::string expected;  // a part of the error message
};

TEST(PolicyFileTest, HostileInputGivesANamedError) {
  const std::vector<BadCase> cases = {
      {"empty", "", "malformed JSON"},
      {"truncated", "[[1, 2", "malformed JSON"},
      {"trailing garbage", policy_text(zero_texts()) + " x", "malformed JSON"},
      {"NaN literal", policy_text(with(3, "NaN")), "malformed JSON"},
      {"object", R"({"params": [1]})", "top-level array"},
      {"number", "42", "top-level array"},
      {"empty array", "[]", "got 0 elements"},
      {"three elements", policy_text(zero_texts(), "1, 2"), "got 3 elements"},
      {"bare list", policy_text(zero_texts()).substr(1, policy_text(zero_texts()).size() - 2), "got 2804 elements"},
      {"params not array", "[5, 1]", "parameter array"},
      {"too few", policy_text(zero_texts(2803)), "expected 2804 parameters, got 2803"},
      {"too many", policy_text(zero_texts(2805), "1"), "expected 2804 parameters, got 2805"},
      {"none", "[[]]", "expected 2804 parameters, got 0"},
      {"string", policy_text(with(17, "\"0.5\"")), "parameter 17 is not a number"},
      {"null", policy_text(with(18, "null")), "parameter 18 is not a number"},
      {"bool", policy_text(with(19, "true")), "parameter 19 is not a number"},
      {"nested", policy_text(with(20, "[1]")), "parameter 20 is not a number"},
      {"overflow", policy_text(with(5, "1e999")), "not finite"},
      {"negative overflow", policy_text(with(6, "-1e999")), "not finite"},
      {"string score", policy_text(zero_texts(), "\"300\""), "score is not a number"},
      {"null score", policy_text(zero_texts(), "null"), "score is not a number"},
      {"infinite score", policy_text(zero_texts(), "1e999"), "not finite"},
  };
  for (const BadCase& c : cases) {
    const Expected<PolicyFile> r = parse_policy(c.text);
    EXPECT_FALSE(r.has_value()) << c.label;
    EXPECT_NE(r.error().find(c.expected), std::string::npos) << c.label << ": error was \"" << r.error() << "\"";
  }
}

TEST(PolicyFileTest, TextOfInvalidParamsThrows) {
  EXPECT_THROW(policy_json_text(std::vector<double>(2803, 0.0)), std::invalid_argument);
  std::vector<double> p = zero_params();
  p[9] = std::nan("");
  EXPECT_THROW(policy_json_text(p), std::invalid_argument);
  EXPECT_THROW(policy_json_text(zero_params(), HUGE_VAL), std::invalid_argument);
}

TEST_F(PolicyFileDirTest, SaveLoadRoundTripLeavesNoTemporary) {
  const fs::path path = dir_ / "policy.json";
  const std::vector<double> p = tricky_params();
  ASSERT_EQ(save_policy(path, p, -12.5), std::nullopt);
  // overwrite an existing file too
  const std::optional<std::string> error = save_policy(path, p);
  ASSERT_FALSE(error.has_value()) << *error;
  EXPECT_EQ(files(), std::vector<fs::path>{"policy.json"});
  const Expected<PolicyFile> r = load_policy(path);
  ASSERT_TRUE(r) << r.error();
  expect_same_bits(r->params, p);
  EXPECT_FALSE(r->score.has_value());

  ASSERT_EQ(save_policy(path, p, -12.5), std::nullopt);
  EXPECT_EQ(load_policy(path)->score, -12.5);
  EXPECT_EQ(files(), std::vector<fs::path>{"policy.json"});
}

TEST_F(PolicyFileDirTest, SaveOfInvalidParamsWritesNothing) {
  const std::optional<std::string> error = save_policy(dir_ / "bad.json", std::vector<double>(10, 0.0));
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->find("expected 2804 parameters, got 10"), std::string::npos) << *error;
  EXPECT_TRUE(files().empty());
}

TEST_F(PolicyFileDirTest, SaveIntoMissingDirectoryFails) {
  const std::optional<std::string> error = save_policy(dir_ / "absent" / "policy.json", zero_params());
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->find("absent"), std::string::npos) << *error;
  EXPECT_TRUE(files().empty());
}

TEST_F(PolicyFileDirTest, LoadMissingFileFails) {
  const Expected<PolicyFile> r = load_policy(dir_ / "nothing.json");
  EXPECT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("does not exist"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("nothing.json"), std::string::npos) << r.error();
}

TEST_F(PolicyFileDirTest, LoadDirectoryFails) {
  const Expected<PolicyFile> r = load_policy(dir_);
  EXPECT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("directory"), std::string::npos) << r.error();
}

TEST_F(PolicyFileDirTest, LoadErrorNamesFileAndProblem) {
  const fs::path path = dir_ / "short.json";
  std::ofstream(path) << policy_text(zero_texts(100));
  const Expected<PolicyFile> r = load_policy(path);
  EXPECT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("short.json"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("got 100"), std::string::npos) << r.error();
}

TEST_F(PolicyFileDirTest, LoadRefusesHugeFile) {
  const fs::path path = dir_ / "huge.json";
  {
    std::ofstream out(path, std::ios::binary);
    const std::string chunk(1 << 20, ' ');
    for (std::uintmax_t i = 0; i <= kMaxPolicyFileBytes >> 20; ++i) out << chunk;
  }
  const Expected<PolicyFile> r = load_policy(path);
  EXPECT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("larger than"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace poet
