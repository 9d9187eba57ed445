// The project's sine and cosine against the C library's, over many inputs and every size of argument, within the
// bounds math/README.md states; and their values at the edges.

#include "math/trigonometry.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "math_test_support.h"

namespace poet {
namespace {

using math_test::ulps_apart;
using math_test::worst_over;

constexpr int kDraws = 1'000'000;
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(MathSinCos, WithinOneUlpOfTheCLibrary) {
  // small arguments (no reduction), the Cody–Waite range, and beyond it (Payne–Hanek) by exponent
  for (const auto& [lo, hi] : {std::pair{-0.78, 0.78}, {-10.0, 10.0}, {-1e6, 1e6}}) {
    const auto s =
        worst_over([](double x) { return math::sin(x); }, [](double x) { return std::sin(x); }, lo, hi, kDraws, "sin");
    EXPECT_LE(s.ulps, 1u) << "sin over [" << lo << ", " << hi << ") at " << s.at;
    const auto c =
        worst_over([](double x) { return math::cos(x); }, [](double x) { return std::cos(x); }, lo, hi, kDraws, "cos");
    EXPECT_LE(c.ulps, 1u) << "cos over [" << lo << ", " << hi << ") at " << c.at;
  }
  const auto s = worst_over([](double u) { return math::sin(std::exp(u)); },
                            [](double u) { return std::sin(std::exp(u)); }, 14.0, 709.0, kDraws, "sin large");
  EXPECT_LE(s.ulps, 1u) << "sin at exp(" << s.at << ")";
  const auto c = worst_over([](double u) { return math::cos(-std::exp(u)); },
                            [](double u) { return std::cos(-std::exp(u)); }, 14.0, 709.0, kDraws, "cos large");
  EXPECT_LE(c.ulps, 1u) << "cos at -exp(" << c.at << ")";
}

TEST(MathSinCos, SincosIsSinAndCos) {
  RandomStream rng(stream_key(7, "sincos"));
  for (int i = 0; i < 100000; ++i) {
    const double x = rng.uniform(-100.0, 100.0) * (i % 2 ? 1.0 : 1e5);
    const math::SinCos both = math::sincos(x);
    ASSERT_EQ(both.sin, math::sin(x)) << x;
    ASSERT_EQ(both.cos, math::cos(x)) << x;
    // single precision, for Box2D: small (no reduction), reduced, and beyond the float path's bound
    for (const float f : {static_cast<float>(x * 1e-5), static_cast<float>(x * 1e-2), static_cast<float>(x)}) {
      const math::SinCosF pair = math::sincos(f);
      ASSERT_EQ(std::bit_cast<uint32_t>(pair.sin), std::bit_cast<uint32_t>(math::sin(f))) << f;
      ASSERT_EQ(std::bit_cast<uint32_t>(pair.cos), std::bit_cast<uint32_t>(math::cos(f))) << f;
    }
  }
  for (const float f : {0.0f, -0.0f, std::numeric_limits<float>::infinity()}) {
    EXPECT_EQ(std::bit_cast<uint32_t>(math::sincos(f).sin), std::bit_cast<uint32_t>(math::sin(f))) << f;
  }
}

TEST(MathSinCos, Edges) {
  EXPECT_EQ(math::sin(0.0), 0.0);
  EXPECT_TRUE(std::signbit(math::sin(-0.0)));
  EXPECT_EQ(math::cos(0.0), 1.0);
  EXPECT_TRUE(std::isnan(math::sin(kInf)));
  EXPECT_TRUE(std::isnan(math::cos(-kInf)));
  EXPECT_TRUE(std::isnan(math::sin(std::nan(""))));
  EXPECT_EQ(math::sin(0x1p-1074), 0x1p-1074);
  // the doubles nearest a multiple of π/2 among the large ones, where the reduction cancels most
  EXPECT_LE(ulps_apart(math::sin(0x1.6ac5b262ca1ffp+849), std::sin(0x1.6ac5b262ca1ffp+849)), 1u);
  EXPECT_LE(ulps_apart(math::cos(0x1.921fb54442d18p+0), std::cos(0x1.921fb54442d18p+0)), 1u);
  EXPECT_LE(ulps_apart(math::sin(0x1.fffffffffffffp+1023), std::sin(0x1.fffffffffffffp+1023)), 1u);
  EXPECT_LE(ulps_apart(math::sin(1e22), std::sin(1e22)), 1u);
}

TEST(MathSinCosFloat, WithinOneUlpOfTheCLibrary) {
  for (const auto& [lo, hi] : {std::pair{-0.78, 0.78}, {-10.0, 10.0}, {-1e5, 1e5}, {-1e9, 1e9}}) {
    const auto s = worst_over([](double x) { return math::sin(static_cast<float>(x)); },
                              [](double x) { return sinf(static_cast<float>(x)); }, lo, hi, kDraws, "sinf");
    EXPECT_LE(s.ulps, 1u) << "sin(float) over [" << lo << ", " << hi << ") at " << s.at;
    const auto c = worst_over([](double x) { return math::cos(static_cast<float>(x)); },
                              [](double x) { return cosf(static_cast<float>(x)); }, lo, hi, kDraws, "cosf");
    EXPECT_LE(c.ulps, 1u) << "cos(float) over [" << lo << ", " << hi << ") at " << c.at;
  }
  EXPECT_TRUE(std::signbit(math::sin(-0.0f)));
  EXPECT_EQ(math::cos(0.0f), 1.0f);
  EXPECT_TRUE(std::isnan(math::sin(std::numeric_limits<float>::infinity())));
}

TEST(MathSinCosFloat, IsTheDoubleRoundedOnceAlmostAlways) {
  // the single-precision path is shorter, but its error before rounding (below 2^-33) flips a rounding rarely
  RandomStream rng(stream_key(7, "sinf rounding"));
  int differ = 0;
  for (int i = 0; i < kDraws; ++i) {
    const float x = static_cast<float>(rng.uniform(-10.0, 10.0));
    differ += math::sin(x) != static_cast<float>(math::sin(static_cast<double>(x)));
  }
  EXPECT_LE(differ, kDraws / 10000);
}

}  // namespace
}  // namespace poet
