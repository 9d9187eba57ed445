#pragma once
// A policy evaluated on one encoding over a range of terrain seeds: the check a user runs on a policy, and the
// code path of the alignment tests. Episodes are independent rollouts; the result does not depend on `threads`.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "simulation/rollout.h"

namespace poet {

struct CourseSweep {
  std::string course;  // a label: the course name or the encoding's name
  uint32_t first_seed = 0;
  std::vector<RolloutResult> episodes;  // episode i ran on terrain seed first_seed + i (no trajectories)

  double mean_return() const;
  double min_return() const;
  double max_return() const;
  int finished() const;   // ended across the finish line (a last-step fall included)
  int fell() const;       // ended by a hull contact or x < 0
  int timed_out() const;  // neither, at the time limit
  double mean_steps() const;
};

// Requires count >= 1 and first_seed + count <= kMaxEnvSeed (throws std::invalid_argument otherwise).
CourseSweep sweep_course(const Mlp& policy, const std::string& label, const EnvEncoding& encoding, uint32_t first_seed,
                         int count, const WalkerOptions& options = {}, int max_steps = walker::kDefaultTimeLimit,
                         int threads = 1);

// One episode per terrain seed (each below kMaxEnvSeed), episode i on seeds[i], on up to `threads` threads; the
// results do not depend on `threads`. sweep_course is this on consecutive seeds.
std::vector<RolloutResult> run_episodes(const Mlp& policy, const EnvEncoding& encoding, std::span<const uint32_t> seeds,
                                        const WalkerOptions& options, int max_steps, int threads);

}  // namespace poet
