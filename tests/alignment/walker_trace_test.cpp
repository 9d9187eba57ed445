// The walker against step traces of the reference walker on the flat course with the initial push at 0
// (walker-traces/README.md): setup, reset observation, and whole episodes.

#include <gtest/gtest.h>

#include <cmath>

#include "reference_data.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/rollout.h"

namespace poet::alignment {
namespace {

const WalkerOptions kNoPush{.push_scale = 0, .lidar = LidarRule::kNearest};

TEST(WalkerTrace, SetupMatchesReference) {
  POET_REQUIRE_REFERENCE();
  const nlohmann::json t1 = load_trace("T1_zero_action.json");
  const Terrain flat = Terrain::generate({*named_course("flat"), 0});
  WalkerEnv env(flat, kNoPush);
  env.reset();
  const auto bodies = env.body_setup();
  const auto& ref_bodies = t1["setup"]["bodies"];
  ASSERT_EQ(ref_bodies.size(), bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    EXPECT_NEAR(bodies[i].mass, ref_bodies[i]["mass"].get<double>(), 1e-5) << ref_bodies[i]["body"];
    EXPECT_NEAR(bodies[i].inertia, ref_bodies[i]["inertia_about_origin"].get<double>(), 1e-5) << i;
    EXPECT_NEAR(bodies[i].local_center_x, ref_bodies[i]["local_center"][0].get<double>(), 1e-5) << i;
    EXPECT_NEAR(bodies[i].local_center_y, ref_bodies[i]["local_center"][1].get<double>(), 1e-5) << i;
  }
  const auto joints = env.joint_setup();
  const auto& ref_joints = t1["setup"]["joints"];
  for (size_t j = 0; j < joints.size(); ++j) {
    EXPECT_NEAR(joints[j].reference_angle, ref_joints[j]["reference_angle"].get<double>(), 1e-5) << j;
    EXPECT_NEAR(joints[j].lower_limit, ref_joints[j]["lower_limit"].get<double>(), 1e-6) << j;
    EXPECT_NEAR(joints[j].upper_limit, ref_joints[j]["upper_limit"].get<double>(), 1e-6) << j;
  }
  EXPECT_NEAR(walker::kFinishX, t1["setup"]["finish_x"].get<double>(), 1e-9);
  for (const Point& p : flat.ground()) EXPECT_NEAR(p.y, t1["setup"]["ground"]["y"].get<double>(), 1e-12);
  EXPECT_NEAR(flat.ground().back().x, t1["setup"]["ground"]["x_last"].get<double>(), 1e-9);
}

TEST(WalkerTrace, ResetObservationMatchesReference) {
  POET_REQUIRE_REFERENCE();
  const nlohmann::json t1 = load_trace("T1_zero_action.json");
  const Terrain flat = Terrain::generate({*named_course("flat"), 0});
  WalkerEnv env(flat, kNoPush);
  const Observation& obs = env.reset();
  const auto& ref = t1["reset"]["obs"];
  for (size_t i = 0; i < obs.size(); ++i) EXPECT_NEAR(obs[i], ref[i].get<double>(), 1e-3) << "obs[" << i << "]";
  EXPECT_NEAR(env.pose()[0].x, t1["reset"]["hull_x"].get<double>(), 1e-5);
  EXPECT_NEAR(env.pose()[0].y, t1["reset"]["hull_y"].get<double>(), 1e-5);
}

TEST(WalkerTrace, ZeroActionFallsLikeReference) {
  POET_REQUIRE_REFERENCE();
  const nlohmann::json t1 = load_trace("T1_zero_action.json");
  const RolloutResult r =
      rollout(Mlp(zero_params()), Terrain::generate({*named_course("flat"), 0}), kNoPush, {.max_steps = 2000});
  EXPECT_TRUE(r.fell);
  EXPECT_FALSE(r.finished);
  EXPECT_GE(r.steps, 112);
  EXPECT_LE(r.steps, 124);
  EXPECT_NEAR(r.total_reward, t1["summary"]["total_return"].get<double>(), 2.0);
}

TEST(WalkerTrace, TrainedWalkersFinishTheFlatCourseLikeReference) {
  POET_REQUIRE_REFERENCE();
  const nlohmann::json t3 = load_trace("T3_trained_policies.json");
  const Terrain flat = Terrain::generate({*named_course("flat"), 0});
  for (const auto& p : t3["policies"]) {
    std::string file = p["policy_file"];
    file = file.substr(std::string("estool-zoo/").size());  // the trace names files by their path in reference/
    const RolloutResult r = rollout(Mlp(load_zoo_policy(file)), flat, kNoPush);
    EXPECT_TRUE(r.finished) << file;
    EXPECT_FALSE(r.fell) << file;
    EXPECT_NEAR(r.total_reward, p["total_return"].get<double>(), 12.0) << file;
  }
}

}  // namespace
}  // namespace poet::alignment
