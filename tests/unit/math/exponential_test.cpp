// The project's exp, log, tanh and power against the C library's, over many inputs, within the bounds math/README.md
// states; and their values at the edges.

#include "math/exponential.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "math_test_support.h"

namespace poet {
namespace {

using math_test::ulps_apart;
using math_test::worst_over;

constexpr int kDraws = 1'000'000;
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(MathExp, WithinOneUlpOfTheCLibrary) {
  for (const auto& [lo, hi] : {std::pair{-1.0, 1.0}, {-40.0, 40.0}, {-708.0, 709.78}, {-745.0, -708.0}}) {
    const auto worst =
        worst_over([](double x) { return math::exp(x); }, [](double x) { return std::exp(x); }, lo, hi, kDraws, "exp");
    EXPECT_LE(worst.ulps, 1u) << "exp over [" << lo << ", " << hi << ") at " << worst.at;
  }
}

TEST(MathExp, Edges) {
  EXPECT_EQ(math::exp(0.0), 1.0);
  EXPECT_EQ(math::exp(-0.0), 1.0);
  EXPECT_EQ(math::exp(kInf), kInf);
  EXPECT_EQ(math::exp(-kInf), 0.0);
  EXPECT_TRUE(std::isnan(math::exp(std::nan(""))));
  EXPECT_EQ(math::exp(710.0), kInf);
  EXPECT_EQ(math::exp(-746.0), 0.0);
  EXPECT_EQ(math::exp(709.782712893384), std::exp(709.782712893384));  // the largest finite result
  EXPECT_EQ(math::exp(-745.1), std::exp(-745.1));                      // the smallest subnormal
  EXPECT_EQ(math::exp(1.0), 0x1.5bf0a8b145769p+1);                     // e, correctly rounded
}

TEST(MathLog, WithinOneUlpOfTheCLibrary) {
  // near 1 (the hardest part), and x = e^u over the whole range of exponents
  const auto near_one = worst_over([](double x) { return math::log(x); }, [](double x) { return std::log(x); }, 0.5,
                                   2.0, kDraws, "log near 1");
  EXPECT_LE(near_one.ulps, 1u) << "log at " << near_one.at;
  const auto wide = worst_over([](double u) { return math::log(std::exp(u)); },
                               [](double u) { return std::log(std::exp(u)); }, -744.0, 709.0, kDraws, "log wide");
  EXPECT_LE(wide.ulps, 1u) << "log at exp(" << wide.at << ")";
}

TEST(MathLog, Edges) {
  EXPECT_EQ(math::log(1.0), 0.0);
  EXPECT_EQ(math::log(0.0), -kInf);
  EXPECT_EQ(math::log(-0.0), -kInf);
  EXPECT_TRUE(std::isnan(math::log(-1.0)));
  EXPECT_TRUE(std::isnan(math::log(std::nan(""))));
  EXPECT_EQ(math::log(kInf), kInf);
  EXPECT_LE(ulps_apart(math::log(0x1p-1074), std::log(0x1p-1074)), 1u);  // subnormal
  EXPECT_LE(ulps_apart(math::log(0x1.fffffffffffffp+1023), std::log(0x1.fffffffffffffp+1023)), 1u);
  EXPECT_EQ(math::log(2.0), 0x1.62e42fefa39efp-1);  // ln 2, correctly rounded
}

TEST(MathTanh, WithinTwoPointThreeE16OfTheCLibrary) {
  RandomStream rng(stream_key(7, "tanh"));
  double worst = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double x = rng.uniform(-25.0, 25.0);
    worst = std::max(worst, std::abs(math::tanh(x) - std::tanh(x)));
  }
  EXPECT_LE(worst, 2.3e-16);
  EXPECT_EQ(std::signbit(math::tanh(-0.0)), true);
  EXPECT_EQ(math::tanh(0.0), 0.0);
  EXPECT_EQ(math::tanh(kInf), 1.0);
  EXPECT_EQ(math::tanh(-kInf), -1.0);
  EXPECT_EQ(math::tanh(-800.0), -1.0);
}

TEST(MathPower, WithinTheStatedBoundOfTheCLibrary) {
  // ≤ (2 + 2|n·ln b|) ulp: exp(n·ln b) carries ln b's error (1 ulp, up to 2^-52 relative) times n
  for (double b : {0.9, 0.99, 0.999, 0.9999, 0.5, 1.5}) {
    for (uint64_t n = 1; n <= 20000; n += 13) {
      const double want = std::pow(b, static_cast<double>(n));
      if (want < 0x1p-1022 || want > 0x1p1000) continue;  // subnormal or near overflow: not the optimiser's range
      const double bound = 2.0 + 2.0 * std::abs(static_cast<double>(n) * std::log(b));
      EXPECT_LE(static_cast<double>(ulps_apart(math::power(b, n), want)), bound) << b << "^" << n;
    }
  }
  EXPECT_EQ(math::power(0.9, 0), 1.0);
  EXPECT_EQ(math::power(0.0, 0), 1.0);
  EXPECT_EQ(math::power(0.0, 3), 0.0);
  EXPECT_EQ(math::power(1.0, 12345), 1.0);
  EXPECT_EQ(math::power(0.9, 1), 0.9);
}

}  // namespace
}  // namespace poet
