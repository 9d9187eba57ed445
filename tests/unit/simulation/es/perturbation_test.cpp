// Tests simulation/es/perturbation.cpp: ε(key) is a deterministic function of the key, extends by prefix, has the
// moments of N(0, 1), and perturb() is θ ± σε even in place.

#include "simulation/es/perturbation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "simulation/rng.h"

namespace poet {
namespace {

TEST(PerturbationTest, SameKeyGivesSameVector) {
  const uint64_t key = stream_key(7, "noise", {1, 2});
  EXPECT_EQ(perturbation(key, 2804), perturbation(key, 2804));
}

TEST(PerturbationTest, DifferentKeysGiveDifferentVectors) {
  const std::vector<double> a = perturbation(stream_key(7, "noise", {0}), 100);
  const std::vector<double> b = perturbation(stream_key(7, "noise", {1}), 100);
  int equal = 0;
  for (size_t i = 0; i < a.size(); ++i) equal += a[i] == b[i] ? 1 : 0;
  EXPECT_EQ(equal, 0);
}

TEST(PerturbationTest, ShorterFillIsPrefixOfLonger) {
  const uint64_t key = 12345;
  const std::vector<double> longer = perturbation(key, 2804);
  for (size_t n : {0, 1, 2, 7, 8, 1001, 2803}) {
    const std::vector<double> shorter = perturbation(key, n);
    ASSERT_EQ(shorter.size(), n);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(shorter[i], longer[i]) << "n = " << n << ", i = " << i;
  }
}

// The even elements are the cosine half of Box–Muller on the stream's draws in order: element 0 is what
// RandomStream::normal() returns for the same key.
TEST(PerturbationTest, FirstElementIsTheStreamsNormal) {
  const uint64_t key = 99;
  RandomStream rng(key);
  EXPECT_EQ(perturbation(key, 1)[0], rng.normal());
}

// 200k values: the standard error of the mean is 1/√n ≈ 0.0022, of the variance √(2/n) ≈ 0.0032, of the mean
// product of an element pair (cos and sin halves, which must be uncorrelated) √(1/(n/2)) ≈ 0.0032, of the fourth
// moment √(96/n) ≈ 0.022. The bounds are five standard errors; the stream is fixed, so the test is deterministic.
TEST(PerturbationTest, MomentsAreThoseOfStandardNormal) {
  const size_t n = 200000;
  const std::vector<double> z = perturbation(stream_key(3, "noise", {42}), n);
  double sum = 0, sum2 = 0, sum4 = 0, pair_sum = 0;
  for (size_t i = 0; i < n; ++i) {
    sum += z[i];
    sum2 += z[i] * z[i];
    sum4 += z[i] * z[i] * z[i] * z[i];
    if (i % 2 == 0) pair_sum += z[i] * z[i + 1];
  }
  const double mean = sum / n;
  const double variance = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 0.011);
  EXPECT_NEAR(variance, 1.0, 0.016);
  EXPECT_NEAR(sum4 / n, 3.0, 0.11);
  EXPECT_NEAR(pair_sum / (n / 2), 0.0, 0.016);
  for (double x : z) ASSERT_TRUE(std::isfinite(x));
}

TEST(PerturbationTest, PerturbAddsOrSubtractsScaledNoise) {
  const uint64_t key = 5;
  const std::vector<double> theta = {1.0, -2.0, 0.5, 3.0, 0.0};
  const std::vector<double> e = perturbation(key, theta.size());
  const double sigma = 0.1;
  std::vector<double> plus(theta.size()), minus(theta.size());
  perturb(theta, key, +1, sigma, plus);
  perturb(theta, key, -1, sigma, minus);
  for (size_t i = 0; i < theta.size(); ++i) {
    EXPECT_DOUBLE_EQ(plus[i], theta[i] + sigma * e[i]);
    EXPECT_DOUBLE_EQ(minus[i], theta[i] - sigma * e[i]);
  }
}

TEST(PerturbationTest, PerturbInPlace) {
  const uint64_t key = 6;
  std::vector<double> theta = {1.0, -2.0, 0.5};
  std::vector<double> expected(theta.size());
  perturb(theta, key, -1, 0.25, expected);
  perturb(theta, key, -1, 0.25, theta);
  EXPECT_EQ(theta, expected);
}

TEST(PerturbationTest, PerturbRejectsBadArguments) {
  const std::vector<double> theta(3, 0.0);
  std::vector<double> out(3), short_out(2);
  EXPECT_THROW(perturb(theta, 1, +1, 0.1, short_out), std::invalid_argument);
  EXPECT_THROW(perturb(theta, 1, 0, 0.1, out), std::invalid_argument);
  EXPECT_THROW(perturb(theta, 1, 2, 0.1, out), std::invalid_argument);
}

}  // namespace
}  // namespace poet
