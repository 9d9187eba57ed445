#include "simulation/es/optimizer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "math/exponential.h"

namespace poet {
namespace {

// Adam's step size a = lr·√(1−β2ᵗ)/(1−β1ᵗ) for step t ≥ 1: the bias corrections folded into the step, as the
// reference does, so ε is added to the uncorrected √v.
double adam_step_size(double lr, int64_t t, const EsSettings& s) {
  return lr * std::sqrt(1.0 - math::power(s.adam_beta2, static_cast<uint64_t>(t))) / (1.0 - math::power(s.adam_beta1, static_cast<uint64_t>(t)));
}

// One element of an Adam step with step size a: updates m and v and returns the new θ. adam_step and
// adam_proposal both go through here, so a proposal is bit for bit the step it predicts.
inline double adam_element(double theta, double g, double& m, double& v, double a, const EsSettings& s) {
  const double gi = -g + s.l2_coeff * theta;  // Adam descends on −return + L2
  m = s.adam_beta1 * m + (1.0 - s.adam_beta1) * gi;
  v = s.adam_beta2 * v + (1.0 - s.adam_beta2) * gi * gi;
  return theta - a * m / (std::sqrt(v) + s.adam_epsilon);
}

void require_adam_sizes(size_t n, size_t g, const OptimizerState& state, const char* what) {
  if (g != n || state.m.size() != n || state.v.size() != n) {
    throw std::invalid_argument(std::string(what) + ": theta, g and the optimizer state differ in size");
  }
}

}  // namespace

OptimizerState fresh_optimizer(const EsSettings& settings, size_t dim) {
  OptimizerState state;
  state.m.assign(dim, 0.0);
  state.v.assign(dim, 0.0);
  state.t = 0;
  state.lr = settings.init_lr;
  state.sigma = settings.init_sigma;
  return state;
}

void reset(OptimizerState& state, const EsSettings& settings) { state = fresh_optimizer(settings, state.m.size()); }

void adam_step(std::span<double> theta, std::span<const double> g, OptimizerState& state, const EsSettings& settings) {
  require_adam_sizes(theta.size(), g.size(), state, "adam_step");
  state.t += 1;
  const double a = adam_step_size(state.lr, state.t, settings);
  for (size_t i = 0; i < theta.size(); ++i) {
    theta[i] = adam_element(theta[i], g[i], state.m[i], state.v[i], a, settings);
  }
}

std::vector<double> adam_proposal(std::span<const double> theta, std::span<const double> g, const OptimizerState& state,
                                  double lr, const EsSettings& settings) {
  require_adam_sizes(theta.size(), g.size(), state, "adam_proposal");
  // Step t + 1, never t: right after a reset t = 0 and the reference's 1 − β1⁰ = 0 would divide by zero.
  const double a = adam_step_size(lr, state.t + 1, settings);
  std::vector<double> out(theta.size());
  for (size_t i = 0; i < theta.size(); ++i) {
    double m = state.m[i];  // copies: the proposal stores nothing
    double v = state.v[i];
    out[i] = adam_element(theta[i], g[i], m, v, a, settings);
  }
  return out;
}

std::vector<double> sgd_proposal(std::span<const double> theta, std::span<const double> g, double lr, double l2) {
  if (g.size() != theta.size()) throw std::invalid_argument("sgd_proposal: theta and g differ in size");
  std::vector<double> out(theta.size());
  for (size_t i = 0; i < theta.size(); ++i) out[i] = theta[i] + lr * (g[i] - l2 * theta[i]);
  return out;
}

void decay(OptimizerState& state, const EsSettings& settings) {
  state.lr = std::max(state.lr * settings.lr_decay, settings.lr_floor);
  state.sigma = std::max(state.sigma * settings.sigma_decay, settings.sigma_floor);
}

}  // namespace poet
