#include "simulation/envgen/env_encoding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace poet {
namespace {

// roughness 0.3, pits [0, 0.8], stumps w[1, 2] h[0, 0.4] f[0, 1]: a first-generation child of flat
Interval iv(double lo, double hi) { return Interval{lo, hi}; }

EnvEncoding first_child() {
  EnvEncoding e;
  e.roughness = 0.3;
  e.pit_gap = iv(0.0, 0.8);
  e.stump_width = iv(1.0, 2.0);
  e.stump_height = iv(0.0, 0.4);
  e.stump_float = iv(0.0, 1.0);
  return e;
}

EnvEncoding with_stairs() {
  EnvEncoding e = first_child();
  e.stair_height = iv(0.0, 0.4);
  e.stair_width = iv(4.0, 5.0);
  e.stair_steps = iv(1.0, 2.0);
  return e;
}

TEST(EnvEncodingValidate, AcceptsFlatAndFullEncodings) {
  EXPECT_EQ(validate(EnvEncoding{}), std::nullopt);
  EXPECT_EQ(validate(first_child()), std::nullopt);
  EXPECT_EQ(validate(with_stairs()), std::nullopt);
}

TEST(EnvEncodingValidate, AcceptsEqualBoundsOfARealGene) {
  EnvEncoding e = first_child();
  e.pit_gap = iv(8.0, 8.0);
  EXPECT_EQ(validate(e), std::nullopt);
}

struct BadCase {
  const char* what;
  std::function<void(EnvEncoding&)> spoil;
  const char* field;
};

TEST(EnvEncodingValidate, EachBadFieldIsNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const BadCase cases[] = {
      {"roughness NaN", [&](EnvEncoding& e) { e.roughness = nan; }, "ground_roughness"},
      {"roughness negative", [](EnvEncoding& e) { e.roughness = -0.1; }, "ground_roughness"},
      {"roughness too large", [](EnvEncoding& e) { e.roughness = 20.5; }, "ground_roughness"},
      {"gap infinite", [&](EnvEncoding& e) { e.pit_gap = iv(0.0, inf); }, "pit_gap"},
      {"gap negative", [](EnvEncoding& e) { e.pit_gap = iv(-0.4, 0.8); }, "pit_gap"},
      {"gap inverted", [](EnvEncoding& e) { e.pit_gap = iv(1.2, 0.8); }, "pit_gap"},
      {"gap too large", [](EnvEncoding& e) { e.pit_gap = iv(0.0, 20.5); }, "pit_gap"},
      {"stump height inverted", [](EnvEncoding& e) { e.stump_height = iv(0.4, 0.2); }, "stump_height"},
      {"stump width fractional", [](EnvEncoding& e) { e.stump_width = iv(1.0, 2.5); }, "stump_width"},
      {"stump width empty", [](EnvEncoding& e) { e.stump_width = iv(2.0, 2.0); }, "stump_width"},
      {"stump width zero", [](EnvEncoding& e) { e.stump_width = iv(0.0, 1.0); }, "stump_width"},
      {"stump float NaN", [&](EnvEncoding& e) { e.stump_float = iv(nan, 1.0); }, "stump_float"},
      {"stump type partial", [](EnvEncoding& e) { e.stump_float.reset(); }, "stump_float"},
      {"stair height missing",
       [](EnvEncoding& e) {
         e.stair_width = iv(4.0, 5.0);
         e.stair_steps = iv(1.0, 2.0);
       },
       "stair_height"},
      {"stair width zero",
       [](EnvEncoding& e) {
         e.stair_height = iv(0.0, 0.4);
         e.stair_width = iv(0.0, 5.0);
         e.stair_steps = iv(1.0, 2.0);
       },
       "stair_width"},
      {"stair steps zero",
       [](EnvEncoding& e) {
         e.stair_height = iv(0.0, 0.4);
         e.stair_width = iv(4.0, 5.0);
         e.stair_steps = iv(0.0, 2.0);
       },
       "stair_steps"},
  };
  for (const BadCase& c : cases) {
    EnvEncoding e = first_child();
    c.spoil(e);
    const std::optional<std::string> err = validate(e);
    ASSERT_TRUE(err.has_value()) << c.what;
    EXPECT_EQ(err->rfind(c.field, 0), 0u) << c.what << ": " << *err;
  }
}

TEST(EnvEncodingName, FlatIsRoughnessOnly) { EXPECT_EQ(reference_name(EnvEncoding{}), "r0.0"); }

TEST(EnvEncodingName, FirstChildLabel) { EXPECT_EQ(reference_name(first_child()), "r0.3.p0.0_0.8.b1.0_0.0_0.4"); }

TEST(EnvEncodingName, StairsAddStepsLoAndHeightHi) {
  EXPECT_EQ(reference_name(with_stairs()), "r0.3.p0.0_0.8.b1.0_0.0_0.4.s1.0_0.4");
}

TEST(EnvEncodingName, UsesShortestRoundTripDigits) {
  EnvEncoding e;
  e.roughness = 0.1 + 0.2;  // Python prints 0.30000000000000004
  EXPECT_EQ(reference_name(e), "r0.30000000000000004");
  e.roughness = 10.0;
  EXPECT_EQ(reference_name(e), "r10.0");
}

TEST(EnvEncodingName, IgnoresTheNameField) {
  EnvEncoding e = first_child();
  e.name = "something else";
  EXPECT_EQ(reference_name(e), "r0.3.p0.0_0.8.b1.0_0.0_0.4");
}

TEST(EnvEncodingSameGenes, IgnoresNameComparesEveryGene) {
  EnvEncoding a = with_stairs();
  EnvEncoding b = with_stairs();
  b.name = "other";
  EXPECT_TRUE(a.same_genes(b));
  b.stair_steps = iv(1.0, 3.0);
  EXPECT_FALSE(a.same_genes(b));
  b = a;
  b.stump_float.reset();
  EXPECT_FALSE(a.same_genes(b));
}

}  // namespace
}  // namespace poet
