#include "simulation/rollout.h"

#include <gtest/gtest.h>

#include "simulation/envgen/named_courses.h"
#include "simulation/rng.h"

namespace poet {
namespace {

std::vector<double> policy_params(uint64_t seed) {
  RandomStream rng(stream_key(seed, "init"));
  return random_params(rng);
}

TEST(Rollout, RandomPolicyOnFlatGroundNeverFinishesAndCountsEveryStep) {
  for (uint64_t p = 0; p < 6; ++p) {
    const RolloutResult r = rollout(policy_params(p), EnvDef{EnvEncoding{}, 3});
    EXPECT_FALSE(r.finished);
    EXPECT_GE(r.steps, 1);
    EXPECT_LE(r.steps, walker::kDefaultTimeLimit);
    EXPECT_EQ(r.timed_out(), r.steps == walker::kDefaultTimeLimit && !r.fell);
    if (r.fell) {
      EXPECT_LT(r.total_reward, -50);  // the -100 of the last step is in the return
    }
    EXPECT_LT(r.final_x, 10.0);  // random policies never leave the start pad
  }
}

TEST(Rollout, TimeLimitAndTrajectoryRecording) {
  const Terrain t = Terrain::generate({*named_course("r1"), 5});
  const Mlp policy(zero_params());
  const RolloutResult r = rollout(policy, t, {}, {.max_steps = 10, .record_trajectory = true});
  EXPECT_EQ(r.steps, 10);
  EXPECT_TRUE(r.timed_out());
  ASSERT_EQ(r.trajectory.size(), 11u);  // the reset pose, then one per step
  EXPECT_FLOAT_EQ(r.trajectory.back()[0].x, float(r.final_x));
  EXPECT_TRUE(rollout(policy, t, {}, {.max_steps = 10}).trajectory.empty());
}

TEST(Rollout, IsAPureFunctionOfItsInputs) {
  const Terrain hard = Terrain::generate({*named_course("hardcore-like"), 9});
  const Mlp a(policy_params(1)), b(policy_params(2));
  const RolloutResult first = rollout(a, hard);
  rollout(b, hard);
  const RolloutResult again = rollout(a, hard);
  EXPECT_EQ(first.total_reward, again.total_reward);
  EXPECT_EQ(first.steps, again.steps);
  EXPECT_EQ(first.final_x, again.final_x);
}

TEST(Rollout, PushScaleAndLidarRuleAreHonoured) {
  const Terrain flat = Terrain::generate({EnvEncoding{}, 4});
  const Mlp policy(policy_params(3));
  const RolloutResult pushed = rollout(policy, flat, {.push_scale = 5});
  const RolloutResult still = rollout(policy, flat, {.push_scale = 0});
  EXPECT_NE(pushed.total_reward, still.total_reward);
  const RolloutResult first_hit = rollout(policy, flat, {.lidar = LidarRule::kFirst});
  EXPECT_EQ(first_hit.total_reward, pushed.total_reward);  // on flat ground there is one ground hit per ray
}

}  // namespace
}  // namespace poet
