#include "simulation/arithmetic_probe.h"

#include <box2d/box2d.h>

#include <bit>

#include "math/exponential.h"
#include "math/trigonometry.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/es/perturbation.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_env.h"

namespace poet {
namespace {

// Folds values into a digest by their bit patterns (-0.0 and 0.0 apart).
class Digest {
 public:
  explicit Digest(std::string_view name) : h_(hash_name(name)) {}
  void add(uint64_t x) { h_ = mix64(h_ ^ (x + kGoldenGamma)); }
  void add(double x) { add(std::bit_cast<uint64_t>(x)); }
  void add(float x) { add(static_cast<uint64_t>(std::bit_cast<uint32_t>(x))); }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_;
};

// Inputs drawn by the generator's uniform draws only (integer arithmetic and exact scalings), so the inputs
// themselves do not depend on the functions probed.
uint64_t probe_math() {
  Digest d("arithmetic probe: math");
  RandomStream rng(stream_key(0, "arithmetic probe"));
  for (int i = 0; i < 512; ++i) {
    const double small = rng.uniform(-3.0, 3.0);
    const double wide = rng.uniform(-700.0, 700.0);
    // finite, 2 ≤ x < 2^1023: a random mantissa under a random exponent (never ∞ or NaN, whose bits no one asks).
    // Every draw is a statement of its own: the order of a call's arguments or of an operator's operands is the
    // compiler's to choose, and differs between x86-64 and arm64.
    const uint64_t mantissa = rng.next_u64() >> 12;
    const uint64_t exponent = 0x400 + rng.next_u64() % 0x3ff;
    const double huge = std::bit_cast<double>(mantissa | (exponent << 52));
    const double base = rng.uniform(0.5, 1.0);
    const uint64_t power = rng.next_u64() % 5000;
    d.add(math::exp(small));
    d.add(math::exp(wide));
    d.add(math::log(4.0 * base - 2.0));  // (0, 2)
    d.add(math::log(huge));
    d.add(math::tanh(small));
    d.add(math::power(base, power));
    for (double x : {small, wide, huge}) {
      const math::SinCos both = math::sincos(x);
      d.add(both.sin);
      d.add(both.cos);
      d.add(math::sin(static_cast<float>(x)));
      d.add(math::cos(static_cast<float>(x)));
    }
  }
  double noise[64];
  fill_perturbation(stream_key(0, "arithmetic probe noise"), noise);
  for (double z : noise) d.add(z);
  return d.value();
}

// A box dropped at an angle onto a static edge, and two boxes joined by a motored revolute joint with limits.
uint64_t probe_box2d() {
  b2World world(b2Vec2(0.0f, -10.0f));
  b2BodyDef ground_def;
  b2Body* ground = world.CreateBody(&ground_def);
  b2EdgeShape edge;
  edge.SetTwoSided(b2Vec2(-20.0f, 0.0f), b2Vec2(20.0f, 0.3f));
  ground->CreateFixture(&edge, 0.0f);
  b2PolygonShape box;
  box.SetAsBox(0.5f, 0.25f);
  auto dynamic = [&](float x, float y, float angle) {
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position.Set(x, y);
    def.angle = angle;
    b2Body* body = world.CreateBody(&def);
    b2FixtureDef fixture;
    fixture.shape = &box;
    fixture.density = 5.0f;
    fixture.friction = 0.6f;
    body->CreateFixture(&fixture);
    return body;
  };
  b2Body* falling = dynamic(0.0f, 3.0f, 0.7f);
  b2Body* upper = dynamic(3.0f, 2.0f, 0.1f);
  b2Body* lower = dynamic(3.0f, 1.2f, -0.2f);
  b2RevoluteJointDef joint;
  joint.Initialize(upper, lower, b2Vec2(3.0f, 1.6f));
  joint.enableMotor = true;
  joint.motorSpeed = 4.0f;
  joint.maxMotorTorque = 80.0f;
  joint.enableLimit = true;
  joint.lowerAngle = -0.8f;
  joint.upperAngle = 1.1f;
  world.CreateJoint(&joint);
  Digest d("arithmetic probe: box2d");
  for (int step = 0; step < 120; ++step) {
    world.Step(1.0f / 50.0f, 6, 2);
    for (const b2Body* body : {falling, upper, lower}) {
      d.add(body->GetPosition().x);
      d.add(body->GetPosition().y);
      d.add(body->GetAngle());
      d.add(body->GetLinearVelocity().x);
      d.add(body->GetAngularVelocity());
    }
  }
  return d.value();
}

// The walker on a course with stumps, pits and rough ground, driven by a fixed random policy.
uint64_t probe_walker() {
  const Terrain terrain = Terrain::generate(EnvDef{*named_course("hardcore-like"), 3});
  RandomStream init(stream_key(0, "arithmetic probe policy"));
  const Mlp policy(random_params(init, 0.3));
  WalkerEnv env(terrain);
  const Observation* obs = &env.reset();
  Digest d("arithmetic probe: walker");
  for (int step = 0; step < 150; ++step) {
    const StepOutcome outcome = env.step(policy.act(*obs));
    obs = &env.observation();
    for (double v : *obs) d.add(v);
    d.add(outcome.reward);
    if (outcome.done()) obs = &env.reset();
  }
  return d.value();
}

}  // namespace

uint64_t ArithmeticProbe::digest() const { return mix64(mix64(mix64(math) ^ box2d) ^ walker); }

ArithmeticProbe probe_arithmetic() {
  static const ArithmeticProbe probe{probe_math(), probe_box2d(), probe_walker()};
  return probe;
}

}  // namespace poet
