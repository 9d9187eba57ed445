#pragma once
// The ES step both es_bench and dispatch_bench time: 64 mirrored perturbations (128 rollouts; the reference's 256
// scale the same way) of a random θ (N(0, 0.1²)) on the r1 course (seed 17), then the gradient and Adam.

#include <cstdint>
#include <vector>

#include "engine/rollout_batch.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/es/es_settings.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {

struct EsStepFixture {
  static constexpr int kPerturbations = 64;
  EpisodeSettings episodes{WalkerOptions{}, 2000, false, 1, std::nullopt};
  EsSettings es;
  EnvDef env{*named_course("r1"), 17};
  std::vector<double> theta;

  EsStepFixture() {
    RandomStream init(stream_key(2024, "bench-es", {0}));
    theta = random_params(init, 0.1);
    es.perturbations = kPerturbations;
  }

  // Adds step number `step` (its own perturbation keys) to the batch; the handle of its results.
  size_t add_step(RolloutBatch& batch, uint64_t step) const {
    return batch.add_es_step({share(theta), env, 0.1, stream_key(2024, "bench-noise", {step})}, kPerturbations);
  }
};

}  // namespace poet
