#pragma once
// Distribution statistics of courses and of random initial policies over many terrain seeds: what the walker
// domain looks like in aggregate, comparable with the reference's figures (docs/fidelity.md).

#include <cstdint>

#include "simulation/envgen/env_encoding.h"
#include "simulation/walker/walker_env.h"

namespace poet {

struct TerrainStatistics {
  double mean_abs_dy = 0;  // over the 199 gaps between consecutive ground points, metres
  double obstacles = 0;    // obstacles per course (a pit, a stump, a staircase each count once)
  double pits = 0, stumps = 0, stairs = 0;
  double mean_pit_width = 0, mean_stump_height = 0;  // terrain steps, as sampled (0 when none)
};

// Courses of `encoding` with terrain seeds [first_seed, first_seed + count).
TerrainStatistics terrain_statistics(const EnvEncoding& encoding, uint32_t first_seed, int count);

struct RandomPolicyStatistics {
  double median_return = 0;
  double fell = 0, timed_out = 0, finished = 0;  // fractions of the episodes
  double median_steps = 0;
};

// `policies` random initial policies θ ~ N(0, 0.1²) (policy i drawn from stream (seed, "init", i)), policy i on
// terrain seed i mod 50, 2000-step limit: the reference's protocol in STATISTICS.md.
RandomPolicyStatistics random_policy_statistics(const EnvEncoding& encoding, int policies, uint64_t seed,
                                                const WalkerOptions& options = {}, int threads = 1);

}  // namespace poet
