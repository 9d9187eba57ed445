#pragma once
// One episode of a policy on a course: the single simulation path that workers and the local evaluator share.
// A rollout is a pure function of (policy parameters, course, options, limits).

#include <span>
#include <stop_token>
#include <vector>

#include "simulation/envgen/env_encoding.h"
#include "simulation/policy/mlp.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_constants.h"
#include "simulation/walker/walker_env.h"

namespace poet {

struct RolloutLimits {
  int max_steps = walker::kDefaultTimeLimit;  // steps after the reset step
  bool record_trajectory = false;             // keep the walker's pose after reset and after every step
  std::stop_token stop{};                     // a stop request ends the episode early (result.stopped)
};

struct RolloutResult {
  double total_reward = 0;  // sum of step rewards after the reset step
  int steps = 0;            // steps taken after the reset step (the reference logs steps − 1)
  bool finished = false;
  bool fell = false;
  double final_x = 0;                  // hull origin x at the end, metres
  bool stopped = false;                // cut short by limits.stop: not a whole episode, its numbers mean nothing
  std::vector<WalkerPose> trajectory;  // reset pose, then one per step, when recorded
  bool timed_out() const { return !finished && !fell; }
};

RolloutResult rollout(const Mlp& policy, const Terrain& terrain, const WalkerOptions& options = {},
                      const RolloutLimits& limits = {});

// Convenience for one-off episodes: generates the course and the network, then runs the rollout above.
RolloutResult rollout(std::span<const double> params, const EnvDef& env, const WalkerOptions& options = {},
                      const RolloutLimits& limits = {});

}  // namespace poet
