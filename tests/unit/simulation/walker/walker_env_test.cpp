#include "simulation/walker/walker_env.h"

#include <gtest/gtest.h>

#include <cmath>

#include "simulation/rng.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

using namespace walker;

Terrain course(double roughness, uint32_t seed) {
  EnvEncoding e;
  e.roughness = roughness;
  return Terrain::generate({e, seed});
}

Terrain hard_course(uint32_t seed) {
  EnvEncoding e;
  e.roughness = 3;
  e.pit_gap = Interval{2, 4};
  e.stump_width = Interval{1, 2};
  e.stump_height = Interval{1.5, 2.5};
  e.stump_float = Interval{0, 1};
  return Terrain::generate({e, seed});
}

// A hash of every number the walker reports, to compare whole trajectories.
uint64_t hash_step(uint64_t h, const Observation& obs, double reward) {
  for (double v : obs) h = mix64(h ^ std::bit_cast<uint64_t>(v));
  return mix64(h ^ std::bit_cast<uint64_t>(reward));
}

uint64_t run_scripted(const Terrain& t, int steps) {
  WalkerEnv env(t);
  uint64_t h = hash_step(0, env.reset(), 0);
  for (int k = 0; k < steps; ++k) {
    const Action a = {0.8 * std::sin(0.1 * k), 0.8 * std::cos(0.13 * k), 0.8 * std::sin(0.07 * k + 1),
                      0.8 * std::cos(0.11 * k + 2)};
    const StepOutcome out = env.step(a);
    h = hash_step(h, env.observation(), out.reward);
    if (out.done()) break;
  }
  return h;
}

TEST(WalkerEnv, BuildsTheReferenceBodiesAndJoints) {
  const Terrain t = course(0, 0);
  WalkerEnv env(t, {.push_scale = 0});
  env.reset();
  const auto bodies = env.body_setup();
  // Hull polygon area 0.54222 m² × density 5; legs 8×34 px and 6.4×34 px at density 1.
  EXPECT_NEAR(bodies[0].mass, 5.4222226, 1e-5);
  EXPECT_NEAR(bodies[1].mass, 0.3022222, 1e-6);
  EXPECT_NEAR(bodies[2].mass, 0.2417778, 1e-6);
  EXPECT_NEAR(bodies[3].mass, bodies[1].mass, 0);
  EXPECT_NEAR(bodies[4].mass, bodies[2].mass, 0);
  const auto joints = env.joint_setup();
  const float ref[4] = {-0.05f, 0.0f, 0.05f, 0.0f};
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(joints[j].reference_angle, ref[j], 1e-7) << j;
    EXPECT_FLOAT_EQ(joints[j].lower_limit, j % 2 == 0 ? -0.8f : -1.6f);
    EXPECT_FLOAT_EQ(joints[j].upper_limit, j % 2 == 0 ? 1.1f : -0.1f);
  }
}

TEST(WalkerEnv, ObservationsStayInTheirRanges) {
  const Terrain t = hard_course(3);
  WalkerEnv env(t);
  env.reset();
  RandomStream rng(stream_key(1, "actions"));
  for (int k = 0; k < 600; ++k) {
    const Action a = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    const StepOutcome out = env.step(a);
    const Observation& o = env.observation();
    for (double v : o) ASSERT_TRUE(std::isfinite(v));
    EXPECT_TRUE(o[8] == 0.0 || o[8] == 1.0);
    EXPECT_TRUE(o[13] == 0.0 || o[13] == 1.0);
    for (int i = 14; i < 24; ++i) {
      EXPECT_GE(o[i], 0.0);
      EXPECT_LE(o[i], 1.0);
    }
    // knee angle + 1 lies within the limits shifted by one (up to the solver's slop)
    EXPECT_GT(o[6], kKneeLower + 1 - 0.2);
    EXPECT_LT(o[6], kKneeUpper + 1 + 0.2);
    if (out.done()) break;
  }
}

TEST(WalkerEnv, ZeroTorqueOnFlatGroundFallsWithMinusHundredAndNeverFinishes) {
  const Terrain t = course(0, 11);
  WalkerEnv env(t);
  env.reset();
  StepOutcome out;
  int steps = 0;
  double total = 0;
  while (steps < kDefaultTimeLimit) {
    out = env.step({0, 0, 0, 0});
    ++steps;
    total += out.reward;
    if (out.done()) break;
  }
  EXPECT_TRUE(out.fell);
  EXPECT_FALSE(out.finished);
  EXPECT_EQ(out.reward, kFallReward);  // replaced, not added to the step's shaping reward
  EXPECT_GT(steps, 80);
  EXPECT_LT(steps, 200);
  EXPECT_GT(env.hull_x(), kInitX);  // collapses forward, far from the finish line
  EXPECT_LT(total, -80);
}

TEST(WalkerEnv, LeavingTheCourseBackwardsEndsWithMinusHundred) {
  // A strong push backwards throws the walker off the left end of the course (x < 0).
  uint32_t seed = 0;
  while (course(0, seed).push_unit() > 0.25) ++seed;  // a seed whose push points left, hard
  const Terrain t = course(0, seed);
  WalkerEnv env(t, {.push_scale = 40000});
  ASSERT_LT(t.push_force(40000), -20000);
  env.reset();
  StepOutcome out;
  for (int k = 0; k < 50 && !out.done(); ++k) out = env.step({0, 0, 0, 0});
  EXPECT_TRUE(out.fell);
  EXPECT_EQ(out.reward, kFallReward);
  EXPECT_LT(env.hull_x(), 0.0);
}

TEST(WalkerEnv, SameCourseAndActionsGiveTheSameTrajectory) {
  const Terrain a = hard_course(5);
  const Terrain b = course(2, 8);
  const uint64_t first = run_scripted(a, 300);
  run_scripted(b, 300);  // another course in between must not leave anything behind
  EXPECT_EQ(run_scripted(a, 300), first);
  EXPECT_NE(run_scripted(b, 300), first);
}

TEST(WalkerEnv, RejectsNonFiniteActionsAndBadOptions) {
  const Terrain t = course(0, 0);
  WalkerEnv env(t);
  EXPECT_THROW(env.step({0, 0, 0, 0}), std::logic_error);  // before reset
  env.reset();
  EXPECT_THROW(env.step({std::nan(""), 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(WalkerEnv(t, {.push_scale = -1}), std::invalid_argument);
}

TEST(WalkerEnv, NearestLidarNeverReadsFartherThanFirstHit) {
  const Terrain t = hard_course(2);
  WalkerEnv nearest(t, {.lidar = LidarRule::kNearest});
  WalkerEnv first(t, {.lidar = LidarRule::kFirst});
  const Observation& a = nearest.reset();
  const Observation& b = first.reset();
  for (int i = 0; i < 14; ++i) EXPECT_EQ(a[i], b[i]);
  for (int i = 14; i < 24; ++i) EXPECT_LE(a[i], b[i]);
}

}  // namespace
}  // namespace poet
