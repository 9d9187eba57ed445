// Tests simulation/policy/mlp.cpp: the parameter layout by hand-computable networks, the arithmetic against a naive
// loop, the boundary checks, and (when the reference data is present) the reference's recorded actions.

#include "simulation/policy/mlp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/formats/policy/policy_file.h"
#include "simulation/rng.h"

namespace poet {
namespace {

// Offsets of each block in the parameter vector.
constexpr int kW1 = 0;
constexpr int kB1 = kW1 + kObsDim * kHidden;
constexpr int kW2 = kB1 + kHidden;
constexpr int kB2 = kW2 + kHidden * kHidden;
constexpr int kW3 = kB2 + kHidden;
constexpr int kB3 = kW3 + kHidden * kActDim;

std::array<double, kObsDim> random_obs(RandomStream& rng) {
  std::array<double, kObsDim> obs;
  for (double& x : obs) x = rng.uniform(-2.0, 2.0);
  return obs;
}

// h ← tanh(h·W + b) written out with loops over the raw layout, sharing no code with Mlp.
std::vector<double> naive_act(const std::vector<double>& p, const std::vector<double>& obs) {
  std::vector<double> h = obs;
  size_t offset = 0;
  for (int out_dim : {kHidden, kHidden, kActDim}) {
    const size_t in_dim = h.size();
    const size_t bias = offset + in_dim * static_cast<size_t>(out_dim);
    std::vector<double> next(static_cast<size_t>(out_dim));
    for (size_t j = 0; j < next.size(); ++j) {
      double sum = 0;
      for (size_t i = 0; i < in_dim; ++i) sum += h[i] * p[offset + i * next.size() + j];
      next[j] = std::tanh(sum + p[bias + j]);
    }
    offset = bias + next.size();
    h = next;
  }
  return h;
}

TEST(MlpTest, ParamCountMatchesLayout) { EXPECT_EQ(kB3 + kActDim, kParamCount); }

TEST(MlpTest, ZeroParamsGiveZeroActions) {
  const Mlp mlp(zero_params());
  RandomStream rng(stream_key(1, "mlp_test"));
  for (int k = 0; k < 10; ++k) {
    for (double a : mlp.act(random_obs(rng))) EXPECT_EQ(a, 0.0);
  }
}

TEST(MlpTest, BiasesOnlyGiveTanhOfLastBias) {
  std::vector<double> p = zero_params();
  for (int i = 0; i < kHidden; ++i) p[kB1 + i] = 0.5 + 0.01 * i;
  for (int i = 0; i < kHidden; ++i) p[kB2 + i] = -0.3 + 0.02 * i;
  for (int j = 0; j < kActDim; ++j) p[kB3 + j] = 0.7 * (j - 1.5);
  const Mlp mlp(p);
  RandomStream rng(stream_key(2, "mlp_test"));
  const auto out = mlp.act(random_obs(rng));
  for (int j = 0; j < kActDim; ++j) EXPECT_NEAR(out[j], std::tanh(p[kB3 + j]), 1e-14) << "output " << j;
}

TEST(MlpTest, BiasChainThroughUnitWeights) {
  // every unit of a layer feeds every unit of the next with weight 1: h2 = tanh(Σ tanh(b1) + b2), etc.
  std::vector<double> p = zero_params();
  for (int i = kW2; i < kB2; ++i) p[i] = 1.0 / kHidden;
  for (int i = kW3; i < kB3; ++i) p[i] = 1.0 / kHidden;
  for (int i = 0; i < kHidden; ++i) p[kB1 + i] = 0.4;
  for (int i = 0; i < kHidden; ++i) p[kB2 + i] = -0.2;
  for (int j = 0; j < kActDim; ++j) p[kB3 + j] = 0.1 * j;
  const Mlp mlp(p);
  std::array<double, kObsDim> obs{};
  obs.fill(3.0);  // W1 is zero: the observation must not matter
  const auto out = mlp.act(obs);
  const double h2 = std::tanh(std::tanh(0.4) - 0.2);
  for (int j = 0; j < kActDim; ++j) EXPECT_NEAR(out[j], std::tanh(h2 + 0.1 * j), 1e-14) << "output " << j;
}

TEST(MlpTest, SinglePathLocatesEachWeight) {
  // one path x3 → h1[7] → h2[5] → out[2], with every bias set, checks each block's offset and orientation
  const double a = 0.9, b = -1.3, c = 1.7;
  std::vector<double> p = zero_params();
  RandomStream rng(stream_key(3, "mlp_test"));
  for (int i = kB1; i < kW2; ++i) p[i] = rng.uniform(-1, 1);
  for (int i = kB2; i < kW3; ++i) p[i] = rng.uniform(-1, 1);
  for (int i = kB3; i < kParamCount; ++i) p[i] = rng.uniform(-1, 1);
  p[kW1 + 3 * kHidden + 7] = a;
  p[kW2 + 7 * kHidden + 5] = b;
  p[kW3 + 5 * kActDim + 2] = c;
  const Mlp mlp(p);
  for (double x3 : {-2.0, -0.25, 0.0, 0.5, 3.0}) {
    std::array<double, kObsDim> obs{};
    obs.fill(100.0);  // inputs other than x3 have zero weights
    obs[3] = x3;
    const auto out = mlp.act(obs);
    const double h1 = std::tanh(a * x3 + p[kB1 + 7]);
    const double h2 = std::tanh(b * h1 + p[kB2 + 5]);
    EXPECT_NEAR(out[2], std::tanh(c * h2 + p[kB3 + 2]), 1e-14) << "x3 = " << x3;
    for (int j : {0, 1, 3}) EXPECT_NEAR(out[j], std::tanh(p[kB3 + j]), 1e-14) << "output " << j;
  }
}

TEST(MlpTest, MatchesNaiveLoopOnRandomNetworks) {
  RandomStream rng(stream_key(4, "mlp_test"));
  double max_diff = 0;
  for (int net = 0; net < 20; ++net) {
    const std::vector<double> p = random_params(rng, 0.5);
    const Mlp mlp(p);
    for (int k = 0; k < 50; ++k) {
      const auto obs = random_obs(rng);
      const auto out = mlp.act(obs);
      const auto expected = naive_act(p, std::vector<double>(obs.begin(), obs.end()));
      for (int j = 0; j < kActDim; ++j) max_diff = std::max(max_diff, std::abs(out[j] - expected[j]));
    }
  }
  EXPECT_LT(max_diff, 1e-12);
}

TEST(MlpTest, SaturatesCleanlyWithHugeWeights) {
  // pre-activations in the thousands: outputs must be ±1 (or near), never NaN
  RandomStream rng(stream_key(7, "mlp_test"));
  const std::vector<double> p = random_params(rng, 50.0);
  const Mlp mlp(p);
  for (int k = 0; k < 50; ++k) {
    const auto obs = random_obs(rng);
    const auto out = mlp.act(obs);
    const auto expected = naive_act(p, std::vector<double>(obs.begin(), obs.end()));
    for (int j = 0; j < kActDim; ++j) {
      ASSERT_TRUE(std::isfinite(out[j]));
      EXPECT_LE(std::abs(out[j]), 1.0);
      EXPECT_NEAR(out[j], expected[j], 1e-12);
    }
  }
}

TEST(MlpTest, ParamsRoundTrip) {
  RandomStream rng(stream_key(5, "mlp_test"));
  const std::vector<double> p = random_params(rng);
  EXPECT_EQ(Mlp(p).params(), p);
}

TEST(MlpTest, RejectsWrongSize) {
  for (size_t n : {size_t{0}, size_t{2803}, size_t{2805}}) {
    const std::vector<double> p(n, 0.0);
    try {
      Mlp mlp(p);
      FAIL() << "accepted " << n << " parameters";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("2804"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(n)), std::string::npos) << e.what();
    }
  }
}

TEST(MlpTest, RejectsNonFinite) {
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    std::vector<double> p = zero_params();
    p[1234] = bad;
    try {
      Mlp mlp(p);
      FAIL() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("1234"), std::string::npos) << e.what();
    }
  }
}

TEST(MlpTest, RandomParamsAreDeterministicNormal) {
  RandomStream a(stream_key(6, "mlp_test")), b(stream_key(6, "mlp_test"));
  const std::vector<double> p = random_params(a, 0.1);
  EXPECT_EQ(p, random_params(b, 0.1));
  EXPECT_EQ(a.counter(), 2u * kParamCount);  // two draws per normal
  ASSERT_EQ(p.size(), static_cast<size_t>(kParamCount));
  double sum = 0, sum_sq = 0;
  for (double x : p) {
    sum += x;
    sum_sq += x * x;
  }
  const double mean = sum / kParamCount;
  const double sd = std::sqrt(sum_sq / kParamCount - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);  // 5 standard errors
  EXPECT_NEAR(sd, 0.1, 0.01);
  // stddev scales the same draws
  RandomStream c(stream_key(6, "mlp_test"));
  const std::vector<double> q = random_params(c, 0.3);
  EXPECT_DOUBLE_EQ(q[17], 3.0 * p[17]);
}

// The reference's trained walkers (walker-traces/T3): our network on the recorded observations must give the
// recorded actions. Optional data; the tests above cover the layout and arithmetic without it.
TEST(MlpTest, ReproducesReferenceActions) {
  const std::filesystem::path ref = POET_REFERENCE_DIR;
  if (ref.empty()) GTEST_SKIP() << "POET_REFERENCE_DIR is not set (the reference data is optional; tests/README.md)";
  const std::filesystem::path traces = ref / "walker-traces" / "T3_trained_policies.json";
  if (!std::filesystem::exists(traces)) {
    GTEST_SKIP() << "reference data not present (" << traces.string() << "); it is optional";
  }
  std::ifstream in(traces);
  const nlohmann::json doc = nlohmann::json::parse(in);
  ASSERT_FALSE(doc.at("policies").empty());
  for (const auto& policy : doc.at("policies")) {
    const std::string name = policy.at("policy_file").get<std::string>();
    // the recorded name starts with "estool-zoo/"; accept a bare name under estool-zoo/ too
    std::filesystem::path file = ref / name;
    if (!std::filesystem::exists(file)) file = ref / "estool-zoo" / name;
    const Expected<PolicyFile> loaded = load_policy(file);
    ASSERT_TRUE(loaded) << loaded.error();
    const Mlp mlp(loaded->params);

    std::vector<double> obs = policy.at("reset").at("obs").get<std::vector<double>>();
    const auto& steps = policy.at("first_50_steps");
    ASSERT_EQ(steps.size(), 50u) << name;
    for (const auto& step : steps) {
      ASSERT_EQ(obs.size(), static_cast<size_t>(kObsDim));
      const auto action = mlp.act(std::span<const double, kObsDim>(obs.data(), kObsDim));
      const auto expected = step.at("action").get<std::vector<double>>();
      ASSERT_EQ(expected.size(), static_cast<size_t>(kActDim));
      for (int j = 0; j < kActDim; ++j) {
        EXPECT_NEAR(action[j], expected[j], 1e-9) << name << " step " << step.at("step") << " output " << j;
      }
      obs = step.at("obs").get<std::vector<double>>();
    }
  }
}

}  // namespace
}  // namespace poet
