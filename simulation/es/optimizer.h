#pragma once
// The per-pair optimizer of spec §2: Adam in the reference's form on −g + λθ, the Adam and SGD proposals (which
// compute an update and store nothing), the learning-rate and σ decays with floors, and reset. g is the ES
// gradient estimate (an ascent direction on the return).

#include <cstdint>
#include <span>
#include <vector>

#include "simulation/es/es_settings.h"

namespace poet {

// Adam's moments and step count, and the pair's current learning rate and noise σ. A value type; a checkpoint
// stores it field by field.
struct OptimizerState {
  std::vector<double> m;
  std::vector<double> v;
  int64_t t = 0;
  double lr = 0;
  double sigma = 0;
  friend bool operator==(const OptimizerState&, const OptimizerState&) = default;
};

// Zero moments of `dim` numbers, t = 0, lr and σ at their initial values.
OptimizerState fresh_optimizer(const EsSettings& settings, size_t dim);

// Back to fresh_optimizer(settings, state.m.size()) (after an accepted transfer).
void reset(OptimizerState& state, const EsSettings& settings);

// One Adam step in place: g' = −g + λθ; t += 1; a = lr·√(1−β2ᵗ)/(1−β1ᵗ); m = β1·m + (1−β1)·g';
// v = β2·v + (1−β2)·g'²; θ += −a·m/(√v + ε). Uses state.lr; does not decay.
void adam_step(std::span<double> theta, std::span<const double> g, OptimizerState& state, const EsSettings& settings);

// The θ that adam_step would produce from this state (bias correction of step t + 1), with `lr`; the state is
// not changed.
std::vector<double> adam_proposal(std::span<const double> theta, std::span<const double> g, const OptimizerState& state,
                                  double lr, const EsSettings& settings);

// θ + lr·(g − λθ).
std::vector<double> sgd_proposal(std::span<const double> theta, std::span<const double> g, double lr, double l2);

// After a real step: lr ← max(lr·lr_decay, lr_floor); σ ← max(σ·sigma_decay, sigma_floor).
void decay(OptimizerState& state, const EsSettings& settings);

}  // namespace poet
