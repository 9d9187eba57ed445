// Tests simulation/es/optimizer.cpp: Adam in the reference's form against hand arithmetic and against textbook Adam
// (bias-corrected moments) written out separately, the proposals, the decays with their floors, and reset.

#include "simulation/es/optimizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace poet {
namespace {

// lr 0.01, λ 0.01, β1 0.9, β2 0.999, ε 1e-8: the defaults, spelled out because the hand arithmetic uses them.
EsSettings settings() {
  EsSettings s;
  s.init_lr = 0.01;
  s.l2_coeff = 0.01;
  s.adam_beta1 = 0.9;
  s.adam_beta2 = 0.999;
  s.adam_epsilon = 1e-8;
  return s;
}

// A few ulps of x: the moments are computed in a different order than the expectations (1 − 0.999 is not exactly
// 0.001 in binary), which moves the last digits.
double tolerance(double x) { return 1e-14 * std::abs(x); }

TEST(OptimizerTest, FreshState) {
  const OptimizerState state = fresh_optimizer(settings(), 3);
  EXPECT_EQ(state.m, std::vector<double>(3, 0.0));
  EXPECT_EQ(state.v, std::vector<double>(3, 0.0));
  EXPECT_EQ(state.t, 0);
  EXPECT_EQ(state.lr, 0.01);
  EXPECT_EQ(state.sigma, settings().init_sigma);
}

// θ = (1, −2), g = (0.5, −3): g' = −g + λθ = (−0.49, 2.98). Step 1: a = lr·√(1 − β2)/(1 − β1) = 0.1·√0.001,
// m = 0.1·g', v = 0.001·g'², √v = √0.001·|g'|, so θ₁ = θ − 0.1√0.001·0.1g'/(√0.001|g'| + 1e-8):
//   θ₁[0] = 1 + 0.0049√0.001/(0.49√0.001 + 1e-8) = 1.01 − 0.01·1e-8/(0.49·0.0316228) ≈ 1.01 − 6.4536e-9
//   θ₁[1] = −2 − 0.0298√0.001/(2.98√0.001 + 1e-8) = −2.01 + 0.01·1e-8/(2.98·0.0316228) ≈ −2.01 + 1.0612e-9
TEST(OptimizerTest, AdamFirstStepByHand) {
  const EsSettings s = settings();
  OptimizerState state = fresh_optimizer(s, 2);
  std::vector<double> theta = {1.0, -2.0};
  const std::vector<double> g = {0.5, -3.0};
  adam_step(theta, g, state, s);
  const double r = std::sqrt(0.001);
  EXPECT_NEAR(theta[0], 1.0 + 0.0049 * r / (0.49 * r + 1e-8), 1e-15);
  EXPECT_NEAR(theta[1], -2.0 - 0.0298 * r / (2.98 * r + 1e-8), 1e-15);
  EXPECT_NEAR(theta[0], 1.01 - 6.4536e-9, 1e-13);
  EXPECT_NEAR(theta[1], -2.01 + 1.0612e-9, 1e-13);
  EXPECT_EQ(state.t, 1);
  EXPECT_NEAR(state.m[0], -0.049, tolerance(0.049));
  EXPECT_NEAR(state.m[1], 0.298, tolerance(0.298));
  EXPECT_NEAR(state.v[0], 0.001 * 0.49 * 0.49, tolerance(0.00024));
  EXPECT_NEAR(state.v[1], 0.001 * 2.98 * 2.98, tolerance(0.0089));
  EXPECT_EQ(state.lr, 0.01);  // adam_step does not decay
  EXPECT_EQ(state.sigma, s.init_sigma);
}

// Textbook Adam (Kingma & Ba) on the same g': m̂ = m/(1 − β1ᵗ), v̂ = v/(1 − β2ᵗ), θ −= lr·m̂/(√v̂ + ε̂). The
// reference's form equals it with ε̂ = ε/√(1 − β2ᵗ) (multiply numerator and denominator by √(1 − β2ᵗ)).
TEST(OptimizerTest, AdamThreeStepsMatchTextbookAdam) {
  const EsSettings s = settings();
  OptimizerState state = fresh_optimizer(s, 2);
  state.lr = 0.02;  // the step uses state.lr, not settings.init_lr
  std::vector<double> theta = {1.0, -2.0};
  const std::vector<std::vector<double>> gs = {{0.5, -3.0}, {-1.0, 0.2}, {0.7, 0.7}};

  std::vector<double> ref_theta = theta, ref_m(2, 0.0), ref_v(2, 0.0);
  for (int t = 1; t <= 3; ++t) {
    const std::vector<double>& g = gs[static_cast<size_t>(t - 1)];
    for (size_t i = 0; i < 2; ++i) {
      const double gp = -g[i] + 0.01 * ref_theta[i];
      ref_m[i] = 0.9 * ref_m[i] + 0.1 * gp;
      ref_v[i] = 0.999 * ref_v[i] + 0.001 * gp * gp;
      const double m_hat = ref_m[i] / (1.0 - std::pow(0.9, t));
      const double v_hat = ref_v[i] / (1.0 - std::pow(0.999, t));
      const double eps_hat = 1e-8 / std::sqrt(1.0 - std::pow(0.999, t));
      ref_theta[i] -= 0.02 * m_hat / (std::sqrt(v_hat) + eps_hat);
    }
    adam_step(theta, g, state, s);
    EXPECT_EQ(state.t, t);
    for (size_t i = 0; i < 2; ++i) {
      EXPECT_NEAR(theta[i], ref_theta[i], 1e-14) << "step " << t << ", element " << i;
      EXPECT_NEAR(state.m[i], ref_m[i], tolerance(ref_m[i]));
      EXPECT_NEAR(state.v[i], ref_v[i], tolerance(ref_v[i]));
    }
  }
}

TEST(OptimizerTest, AdamProposalIsTheNextStepAndStoresNothing) {
  const EsSettings s = settings();
  OptimizerState state = fresh_optimizer(s, 2);
  std::vector<double> theta = {0.3, -0.7};
  adam_step(theta, std::vector<double>{1.0, 2.0}, state, s);
  adam_step(theta, std::vector<double>{-0.5, 1.5}, state, s);
  const OptimizerState before = state;
  const std::vector<double> g = {0.25, -4.0};

  for (double lr : {state.lr, 0.003}) {
    const std::vector<double> proposal = adam_proposal(theta, g, state, lr, s);
    EXPECT_EQ(state, before);
    OptimizerState copy = state;
    copy.lr = lr;
    std::vector<double> stepped = theta;
    adam_step(stepped, g, copy, s);
    EXPECT_EQ(proposal, stepped) << "lr " << lr;
  }
}

// Right after a reset t = 0: the proposal uses step 1's bias correction, so it is finite (the reference's t would
// divide by 1 − β1⁰ = 0).
TEST(OptimizerTest, AdamProposalFromFreshStateIsFirstStep) {
  const EsSettings s = settings();
  const OptimizerState state = fresh_optimizer(s, 2);
  const std::vector<double> theta = {1.0, -2.0};
  const std::vector<double> g = {0.5, -3.0};
  const std::vector<double> proposal = adam_proposal(theta, g, state, 0.01, s);
  const double r = std::sqrt(0.001);
  EXPECT_NEAR(proposal[0], 1.0 + 0.0049 * r / (0.49 * r + 1e-8), 1e-15);
  EXPECT_NEAR(proposal[1], -2.0 - 0.0298 * r / (2.98 * r + 1e-8), 1e-15);
}

// θ + lr·(g − λθ) with lr 0.1, λ 0.01: 1 + 0.1·(0.5 − 0.01) = 1.049; −2 + 0.1·(−3 + 0.02) = −2.298.
TEST(OptimizerTest, SgdProposal) {
  const std::vector<double> p = sgd_proposal(std::vector<double>{1.0, -2.0}, std::vector<double>{0.5, -3.0}, 0.1, 0.01);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0], 1.049, 1e-15);
  EXPECT_NEAR(p[1], -2.298, 1e-15);
}

// lr 0.01 halves to 0.005, then 0.0025 < floor 0.003; σ 0.1 → 0.05 → 0.025 → 0.0125 < floor 0.02.
TEST(OptimizerTest, DecayStopsAtFloors) {
  EsSettings s = settings();
  s.lr_decay = 0.5;
  s.lr_floor = 0.003;
  s.init_sigma = 0.1;
  s.sigma_decay = 0.5;
  s.sigma_floor = 0.02;
  OptimizerState state = fresh_optimizer(s, 1);
  decay(state, s);
  EXPECT_DOUBLE_EQ(state.lr, 0.005);
  EXPECT_DOUBLE_EQ(state.sigma, 0.05);
  decay(state, s);
  EXPECT_EQ(state.lr, 0.003);
  EXPECT_DOUBLE_EQ(state.sigma, 0.025);
  decay(state, s);
  EXPECT_EQ(state.lr, 0.003);
  EXPECT_EQ(state.sigma, 0.02);
  decay(state, s);
  EXPECT_EQ(state.lr, 0.003);
  EXPECT_EQ(state.sigma, 0.02);
}

// With the run script's rates: σ reaches 0.01 after ln 10/−ln 0.999 ≈ 2302 decays, lr 0.001 after ≈ 23025.
TEST(OptimizerTest, DefaultDecaysReachFloors) {
  const EsSettings s;
  OptimizerState state = fresh_optimizer(s, 1);
  for (int i = 0; i < 2000; ++i) decay(state, s);
  EXPECT_GT(state.sigma, s.sigma_floor);
  EXPECT_GT(state.lr, s.lr_floor);
  for (int i = 0; i < 30000; ++i) decay(state, s);
  EXPECT_EQ(state.sigma, s.sigma_floor);
  EXPECT_EQ(state.lr, s.lr_floor);
}

TEST(OptimizerTest, ResetRestoresFreshStateOfSameDimension) {
  const EsSettings s = settings();
  OptimizerState state = fresh_optimizer(s, 2);
  std::vector<double> theta = {1.0, 2.0};
  adam_step(theta, std::vector<double>{0.1, -0.1}, state, s);
  decay(state, s);
  ASSERT_NE(state, fresh_optimizer(s, 2));
  reset(state, s);
  EXPECT_EQ(state, fresh_optimizer(s, 2));
}

TEST(OptimizerTest, RejectsMismatchedSizes) {
  const EsSettings s = settings();
  OptimizerState state = fresh_optimizer(s, 2);
  std::vector<double> theta = {1.0, 2.0};
  std::vector<double> long_theta = {1.0, 2.0, 3.0};
  const std::vector<double> g1 = {0.5};
  const std::vector<double> g3 = {0.5, 0.5, 0.5};
  EXPECT_THROW(adam_step(theta, g1, state, s), std::invalid_argument);
  EXPECT_THROW(adam_step(long_theta, g3, state, s), std::invalid_argument);
  EXPECT_EQ(state, fresh_optimizer(s, 2));  // a rejected step changes nothing
  EXPECT_THROW(adam_proposal(theta, g1, state, 0.01, s), std::invalid_argument);
  EXPECT_THROW(adam_proposal(long_theta, g3, state, 0.01, s), std::invalid_argument);
  EXPECT_THROW(sgd_proposal(theta, g1, 0.1, 0.01), std::invalid_argument);
}

}  // namespace
}  // namespace poet
