#include "simulation/walker/walker_env.h"

#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "math/trigonometry.h"
#include "simulation/walker/walker_constants.h"

namespace poet {

using namespace walker;

// Contact flags exactly as the reference keeps them: a hull contact beginning ends the episode; a lower leg's
// flag is set by any contact beginning and cleared by any of its contacts ending (a flag, not a count).
class WalkerEnv::ContactFlags : public b2ContactListener {
 public:
  void BeginContact(b2Contact* contact) override {
    const b2Body* a = contact->GetFixtureA()->GetBody();
    const b2Body* b = contact->GetFixtureB()->GetBody();
    if (a == hull || b == hull) hull_touched = true;
    for (int i = 0; i < 2; ++i)
      if (a == lower[i] || b == lower[i]) ground_contact[i] = true;
  }
  void EndContact(b2Contact* contact) override {
    const b2Body* a = contact->GetFixtureA()->GetBody();
    const b2Body* b = contact->GetFixtureB()->GetBody();
    for (int i = 0; i < 2; ++i)
      if (a == lower[i] || b == lower[i]) ground_contact[i] = false;
  }

  const b2Body* hull = nullptr;
  std::array<const b2Body*, 2> lower{};
  bool hull_touched = false;
  std::array<bool, 2> ground_contact{};
};

namespace {

// Ray-cast callback for one lidar ray. Fractions are relative to the whole ray in both rules.
class LidarRay : public b2RayCastCallback {
 public:
  explicit LidarRay(LidarRule rule) : rule_(rule) {}
  float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float fraction) override {
    if ((fixture->GetFilterData().categoryBits & kGroundCategory) == 0) return -1.0f;  // ignore, continue
    this->fraction = fraction;
    return rule_ == LidarRule::kFirst ? 0.0f : fraction;  // stop, or clip the ray to look for nearer hits
  }
  float fraction = 1.0f;

 private:
  LidarRule rule_;
};

b2FixtureDef ground_fixture(const b2Shape* shape) {
  b2FixtureDef fd;
  fd.shape = shape;
  fd.friction = static_cast<float>(kTerrainFriction);
  fd.filter.categoryBits = kGroundCategory;
  return fd;
}

b2FixtureDef walker_fixture(const b2Shape* shape, double density, double friction) {
  b2FixtureDef fd;
  fd.shape = shape;
  fd.density = static_cast<float>(density);
  fd.friction = static_cast<float>(friction);
  fd.restitution = 0.0f;
  fd.filter.categoryBits = kWalkerCategory;
  fd.filter.maskBits = kGroundCategory;
  return fd;
}

b2Vec2 vec(double x, double y) { return b2Vec2(static_cast<float>(x), static_cast<float>(y)); }

b2RevoluteJoint* make_joint(b2World& world, b2Body* a, b2Body* b, double anchor_a_y, double anchor_b_y, double lower,
                            double upper) {
  b2RevoluteJointDef jd;
  jd.bodyA = a;
  jd.bodyB = b;
  jd.localAnchorA = vec(0, anchor_a_y);
  jd.localAnchorB = vec(0, anchor_b_y);
  // The reference's binding sets the reference angle from the bodies' angles at creation; Box2D 2.4 does not.
  jd.referenceAngle = b->GetAngle() - a->GetAngle();
  jd.enableMotor = true;
  jd.enableLimit = true;
  jd.maxMotorTorque = static_cast<float>(kMotorsTorque);
  jd.lowerAngle = static_cast<float>(lower);
  jd.upperAngle = static_cast<float>(upper);
  return static_cast<b2RevoluteJoint*>(world.CreateJoint(&jd));
}

}  // namespace

WalkerEnv::WalkerEnv(const Terrain& terrain, WalkerOptions options)
    : terrain_(terrain), options_(options), contacts_(std::make_unique<ContactFlags>()) {
  if (!std::isfinite(options_.push_scale) || options_.push_scale < 0)
    throw std::invalid_argument("push_scale must be a finite number >= 0");
}

WalkerEnv::~WalkerEnv() {
  if (world_) world_->SetContactListener(nullptr);
}

void WalkerEnv::build_world() {
  if (world_) world_->SetContactListener(nullptr);
  world_ = std::make_unique<b2World>(vec(0, kGravity));
  // The reference's Box2D 2.3 binding woke the bodies on every motor call, so its walker never slept.
  world_->SetAllowSleeping(false);
  *contacts_ = ContactFlags{};
  world_->SetContactListener(contacts_.get());

  // Bodies in the reference's creation order: obstacle boxes, ground edges, hull, then each leg.
  b2BodyDef static_def;
  for (const TerrainBox& box : terrain_.boxes()) {
    b2PolygonShape shape;
    const b2Vec2 corners[4] = {vec(box.x0, box.y1), vec(box.x1, box.y1), vec(box.x1, box.y0), vec(box.x0, box.y0)};
    shape.Set(corners, 4);
    b2FixtureDef fd = ground_fixture(&shape);
    world_->CreateBody(&static_def)->CreateFixture(&fd);
  }
  const auto& ground = terrain_.ground();
  for (size_t i = 0; i + 1 < ground.size(); ++i) {
    b2EdgeShape shape;
    shape.SetTwoSided(vec(ground[i].x, ground[i].y), vec(ground[i + 1].x, ground[i + 1].y));
    b2FixtureDef fd = ground_fixture(&shape);
    world_->CreateBody(&static_def)->CreateFixture(&fd);
  }

  b2BodyDef body_def;
  body_def.type = b2_dynamicBody;
  body_def.position = vec(kInitX, kInitY);
  hull_ = world_->CreateBody(&body_def);
  {
    b2Vec2 poly[5];
    for (int i = 0; i < 5; ++i) poly[i] = vec(kHullPoly[i][0] / kScale, kHullPoly[i][1] / kScale);
    b2PolygonShape shape;
    shape.Set(poly, 5);
    b2FixtureDef fd = walker_fixture(&shape, kHullDensity, kHullFriction);
    hull_->CreateFixture(&fd);
  }
  hull_->ApplyForceToCenter(vec(terrain_.push_force(options_.push_scale), 0), true);

  b2PolygonShape upper_shape, lower_shape;
  upper_shape.SetAsBox(static_cast<float>(kLegW / 2), static_cast<float>(kLegH / 2));
  lower_shape.SetAsBox(static_cast<float>(kLowerLegWidthFactor * kLegW / 2), static_cast<float>(kLegH / 2));
  for (int side = 0; side < 2; ++side) {
    const double i = side == 0 ? -1.0 : 1.0;
    body_def.angle = static_cast<float>(i * kLegStartAngle);

    body_def.position = vec(kInitX, kInitY - kLegH / 2 - kLegDown);
    b2Body* upper = world_->CreateBody(&body_def);
    b2FixtureDef upper_fd = walker_fixture(&upper_shape, kLegDensity, kLegFriction);
    upper->CreateFixture(&upper_fd);
    joints_[2 * side] = make_joint(*world_, hull_, upper, kLegDown, kLegH / 2, kHipLower, kHipUpper);

    body_def.position = vec(kInitX, kInitY - kLegH * 3 / 2 - kLegDown);
    b2Body* lower = world_->CreateBody(&body_def);
    b2FixtureDef lower_fd = walker_fixture(&lower_shape, kLegDensity, kLegFriction);
    lower->CreateFixture(&lower_fd);
    joints_[2 * side + 1] = make_joint(*world_, upper, lower, -kLegH / 2, kLegH / 2, kKneeLower, kKneeUpper);

    legs_[2 * side] = upper;
    legs_[2 * side + 1] = lower;
  }
  contacts_->hull = hull_;
  contacts_->lower = {legs_[1], legs_[3]};
}

const Observation& WalkerEnv::reset() {
  build_world();
  apply_action({0, 0, 0, 0});
  world_->Step(static_cast<float>(1.0 / kFps), kVelocityIterations, kPositionIterations);
  observe();
  prev_shaping_ = 130.0 * hull_->GetPosition().x / kScale - 5.0 * std::abs(obs_[0]);
  return obs_;
}

void WalkerEnv::apply_action(const Action& action) {
  static constexpr double kSpeeds[4] = {kSpeedHip, kSpeedKnee, kSpeedHip, kSpeedKnee};
  for (int j = 0; j < 4; ++j) {
    const double a = action[j];
    joints_[j]->SetMotorSpeed(static_cast<float>(kSpeeds[j] * ((a > 0) - (a < 0))));
    joints_[j]->SetMaxMotorTorque(static_cast<float>(kMotorsTorque * std::clamp(std::abs(a), 0.0, 1.0)));
  }
}

void WalkerEnv::advance(const Action& action) {
  if (!world_) throw std::logic_error("WalkerEnv::step before reset");
  for (double a : action)
    if (!std::isfinite(a)) throw std::invalid_argument("walker action must be finite");
  apply_action(action);
  world_->Step(static_cast<float>(1.0 / kFps), kVelocityIterations, kPositionIterations);
}

StepOutcome WalkerEnv::step(const Action& action) {
  advance(action);
  observe();

  const double x = hull_->GetPosition().x;
  const double shaping = 130.0 * x / kScale - 5.0 * std::abs(obs_[0]);
  StepOutcome out;
  out.reward = shaping - prev_shaping_;
  prev_shaping_ = shaping;
  for (double a : action) out.reward -= kTorqueCost * kMotorsTorque * std::clamp(std::abs(a), 0.0, 1.0);
  if (contacts_->hull_touched || x < 0) {
    out.reward = kFallReward;  // replaced, not added
    out.fell = true;
  }
  out.finished = x > kFinishX;
  return out;
}

void WalkerEnv::observe() {
  const b2Vec2 pos = hull_->GetPosition();
  const b2Vec2 vel = hull_->GetLinearVelocity();
  obs_[0] = hull_->GetAngle();
  obs_[1] = 2.0 * hull_->GetAngularVelocity() / kFps;
  obs_[2] = 0.3 * vel.x * (600.0 / kScale) / kFps;
  obs_[3] = 0.3 * vel.y * (400.0 / kScale) / kFps;
  for (int side = 0; side < 2; ++side) {
    const b2RevoluteJoint* hip = joints_[2 * side];
    const b2RevoluteJoint* knee = joints_[2 * side + 1];
    double* o = &obs_[4 + 5 * side];
    o[0] = hip->GetJointAngle();
    o[1] = hip->GetJointSpeed() / kSpeedHip;
    o[2] = knee->GetJointAngle() + 1.0;
    o[3] = knee->GetJointSpeed() / kSpeedKnee;
    o[4] = contacts_->ground_contact[side] ? 1.0 : 0.0;
  }
  for (int i = 0; i < kLidarRays; ++i) {
    const math::SinCos ray_direction = math::sincos(1.5 * i / 10.0);
    const b2Vec2 p2 = vec(pos.x + ray_direction.sin * kLidarRange, pos.y - ray_direction.cos * kLidarRange);
    LidarRay ray(options_.lidar);
    world_->RayCast(&ray, pos, p2);
    obs_[14 + i] = ray.fraction;
  }
}

double WalkerEnv::hull_x() const { return hull_->GetPosition().x; }

bool WalkerEnv::hull_touched() const { return contacts_->hull_touched; }

WalkerPose WalkerEnv::pose() const {
  WalkerPose p;
  const b2Body* bodies[5] = {hull_, legs_[0], legs_[1], legs_[2], legs_[3]};
  for (int i = 0; i < 5; ++i) p[i] = {bodies[i]->GetPosition().x, bodies[i]->GetPosition().y, bodies[i]->GetAngle()};
  return p;
}

std::array<BodySetup, 5> WalkerEnv::body_setup() const {
  std::array<BodySetup, 5> s;
  const b2Body* bodies[5] = {hull_, legs_[0], legs_[1], legs_[2], legs_[3]};
  for (int i = 0; i < 5; ++i)
    s[i] = {bodies[i]->GetMass(), bodies[i]->GetInertia(), bodies[i]->GetLocalCenter().x,
            bodies[i]->GetLocalCenter().y};
  return s;
}

std::array<JointSetup, 4> WalkerEnv::joint_setup() const {
  std::array<JointSetup, 4> s;
  for (int j = 0; j < 4; ++j)
    s[j] = {joints_[j]->GetReferenceAngle(), joints_[j]->GetLowerLimit(), joints_[j]->GetUpperLimit()};
  return s;
}

}  // namespace poet
