#include "simulation/rollout.h"

namespace poet {

RolloutResult rollout(const Mlp& policy, const Terrain& terrain, const WalkerOptions& options,
                      const RolloutLimits& limits) {
  WalkerEnv env(terrain, options);
  RolloutResult result;
  const Observation* obs = &env.reset();
  if (limits.record_trajectory) {
    result.trajectory.reserve(static_cast<size_t>(limits.max_steps) + 1);
    result.trajectory.push_back(env.pose());
  }
  // checked every 64 steps (a few milliseconds), so a stop lands well within a second even in long episodes
  constexpr int kStopCheckSteps = 64;
  while (result.steps < limits.max_steps) {
    if (result.steps % kStopCheckSteps == 0 && limits.stop.stop_requested()) {
      result.stopped = true;
      break;
    }
    const StepOutcome out = env.step(policy.act(*obs));
    obs = &env.observation();
    result.total_reward += out.reward;
    result.steps += 1;
    if (limits.record_trajectory) result.trajectory.push_back(env.pose());
    if (out.done()) {
      result.fell = out.fell;
      result.finished = out.finished;
      break;
    }
  }
  result.final_x = env.hull_x();
  return result;
}

RolloutResult rollout(std::span<const double> params, const EnvDef& env, const WalkerOptions& options,
                      const RolloutLimits& limits) {
  return rollout(Mlp(params), Terrain::generate(env), options, limits);
}

}  // namespace poet
