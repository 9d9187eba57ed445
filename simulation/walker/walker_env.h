#pragma once
// The bipedal walker on one course (spec §1): reset builds a fresh Box2D world from the course's cached geometry
// and takes the reset step; step applies one action and advances the world by 1/50 s. Not thread-safe; one
// WalkerEnv per thread. The Terrain must outlive the WalkerEnv.

#include <array>
#include <memory>
#include <span>

#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_constants.h"

class b2World;
class b2Body;
class b2RevoluteJoint;

namespace poet {

using Observation = std::array<double, 24>;
using Action = std::array<double, 4>;  // hip 1, knee 1, hip 2, knee 2; each clipped to [-1, 1] for torque

// Which fixture a lidar ray reports when it crosses several.
enum class LidarRule {
  kNearest = 0,  // the nearest ground hit: the intended reading (and Gym v3's)
  kFirst = 1,    // the first ground fixture Box2D's tree reports, as the reference did (not always the nearest)
  // the numbers are the schema's (WalkerConfig.LidarRule), so its default converts
};

struct WalkerOptions {
  double push_scale = walker::kDefaultPushScale;  // initial horizontal push F ~ U[-push_scale, push_scale) N; 0: none
  LidarRule lidar = static_cast<LidarRule>(schema_defaults::walker_config::lidar);
};

struct StepOutcome {
  double reward = 0;
  bool fell = false;      // the hull touched anything, or x < 0: reward is -100
  bool finished = false;  // the hull crossed the finish line
  bool done() const { return fell || finished; }
};

struct BodyPose {
  float x = 0, y = 0, angle = 0;
};
// Hull, leg 1 upper, leg 1 lower, leg 2 upper, leg 2 lower (Box2D body origins, metres and radians).
using WalkerPose = std::array<BodyPose, 5>;

// Physical facts of the built walker, for alignment checks against the reference.
struct BodySetup {
  float mass, inertia;  // inertia about the body origin
  float local_center_x, local_center_y;
};
struct JointSetup {
  float reference_angle, lower_limit, upper_limit;
};

class WalkerEnv {
 public:
  WalkerEnv(const Terrain& terrain, WalkerOptions options = {});
  ~WalkerEnv();
  WalkerEnv(const WalkerEnv&) = delete;
  WalkerEnv& operator=(const WalkerEnv&) = delete;

  // Builds a fresh world, applies the initial push and takes the reset step (zero action, reward discarded).
  const Observation& reset();
  // One step; the action must be finite (throws std::invalid_argument otherwise). Call reset() first.
  StepOutcome step(const Action& action);
  // Physics only: applies the action and advances the world, leaving observation and reward untouched. The
  // trajectory is the same as step()'s (observing changes nothing); it exists to measure bare physics.
  void advance(const Action& action);

  const Observation& observation() const { return obs_; }
  double hull_x() const;
  bool hull_touched() const;  // a hull contact has begun since reset (the "fell" condition besides x < 0)
  WalkerPose pose() const;
  std::array<BodySetup, 5> body_setup() const;    // same body order as WalkerPose
  std::array<JointSetup, 4> joint_setup() const;  // hip 1, knee 1, hip 2, knee 2

 private:
  class ContactFlags;
  void build_world();
  void apply_action(const Action& action);
  void observe();

  const Terrain& terrain_;
  WalkerOptions options_;
  std::unique_ptr<ContactFlags> contacts_;
  std::unique_ptr<b2World> world_;
  b2Body* hull_ = nullptr;
  std::array<b2Body*, 4> legs_{};  // upper 1, lower 1, upper 2, lower 2
  std::array<b2RevoluteJoint*, 4> joints_{};
  Observation obs_{};
  double prev_shaping_ = 0;
};

}  // namespace poet
