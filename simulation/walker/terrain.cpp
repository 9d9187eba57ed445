#include "simulation/walker/terrain.h"

#include <cmath>
#include <stdexcept>

#include "simulation/envgen/cppn_course.h"
#include "simulation/rng.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

using namespace walker;

// The terrain state machine's states, in the fixed order in which present obstacle types are numbered.
enum class State { kGrass, kStump, kStairs, kPit };

double sign(double v) { return (v > 0) - (v < 0); }

int64_t randint(RandomStream& rng, const Interval& iv) {
  return rng.uniform_int(static_cast<int64_t>(iv.lo), static_cast<int64_t>(iv.hi));
}

// The types of obstacle the encoding has, numbered 1.. in this order, as the reference does.
std::vector<State> present_obstacles(const EnvEncoding& e) {
  std::vector<State> present;
  if (e.has_stumps()) present.push_back(State::kStump);
  if (e.has_stairs()) present.push_back(State::kStairs);
  if (e.has_pits()) present.push_back(State::kPit);
  return present;
}

// The terrain state machine walking a non-CPPN course point by point, drawing from rng as it goes: grass, or an
// obstacle laid out in full at its first point (the oneshot) and then followed by the ground until the counter
// runs out.
class CourseWalk {
 public:
  CourseWalk(const EnvEncoding& e, RandomStream& rng) : e_(e), rng_(rng), present_(present_obstacles(e)) {
    ground.reserve(kTerrainLength);
  }

  std::vector<Point> ground;
  std::vector<TerrainBox> boxes;
  std::vector<ObstacleFeature> features;

  // Point i: the state's work, then the count towards the next state.
  void step(int i) {
    const double x = i * ts;
    ground.push_back({x, 0});

    if (state_ == State::kGrass && !oneshot_) {
      grass(i);
    } else if (state_ == State::kPit && oneshot_) {
      lay_pit(i, x);
    } else if (state_ == State::kPit && !oneshot_) {
      in_pit();
    } else if (state_ == State::kStump && oneshot_) {
      lay_stump(i, x);
    } else if (state_ == State::kStairs && oneshot_) {
      lay_stairs(i, x);
    } else if (state_ == State::kStairs && !oneshot_) {
      on_stairs();
    }

    oneshot_ = false;
    ground.back().y = y_;
    counter_ -= 1;
    if (counter_ == 0) next_state();
  }

 private:
  static constexpr double ts = kTerrainStep;

  void grass(int i) {
    velocity_ = 0.8 * velocity_ + 0.01 * sign(kTerrainHeight - y_);
    if (i > kTerrainStartpad) velocity_ += rng_.uniform(-1, 1) / kScale;
    y_ += e_.roughness * velocity_;
  }

  void lay_pit(int i, double x) {
    const double gap = rng_.uniform(e_.pit_gap->lo, e_.pit_gap->hi);
    const double w = 1.0 + gap;  // wall to wall, in steps
    counter_ = static_cast<int>(std::ceil(w)) + 2;
    pit_diff_ = std::ceil(w) - w;
    original_y_ = y_;
    const double depth = kPitDepthSteps * ts;
    boxes.push_back({ObstacleKind::kPitWall, x, x + ts, y_ - depth, y_});
    boxes.push_back({ObstacleKind::kPitWall, x + w * ts, x + ts + w * ts, y_ - depth, y_});
    features.push_back({ObstacleKind::kPitWall, i, w, kPitDepthSteps});
  }

  void in_pit() {
    y_ = original_y_;
    if (counter_ > 1) y_ -= kPitDepthSteps * ts;
    if (counter_ == 1) {
      ground.back().x -= pit_diff_ * ts;  // the far wall sits at a fractional step: keep the gap continuous
      pit_diff_ = 0;
    }
  }

  void lay_stump(int i, double x) {
    const int width = static_cast<int>(randint(rng_, *e_.stump_width));
    const double height = rng_.uniform(e_.stump_height->lo, e_.stump_height->hi);
    const int lift = static_cast<int>(randint(rng_, *e_.stump_float));
    counter_ = width;
    const double y0 = y_ + lift * ts;
    const double box_h = std::max(height, kMinObstacleHeightSteps);
    boxes.push_back({ObstacleKind::kStump, x, x + width * ts, y0, y0 + box_h * ts});
    features.push_back({ObstacleKind::kStump, i, double(width), height});
  }

  void lay_stairs(int i, double x) {
    stair_height_ = rng_.uniform(e_.stair_height->lo, e_.stair_height->hi);
    stair_dir_ = rng_.uniform01() > 0.5 ? 1 : -1;
    stair_width_ = static_cast<int>(randint(rng_, *e_.stair_width));
    stair_steps_ = static_cast<int>(randint(rng_, *e_.stair_steps));
    original_y_ = y_;
    const double box_h = std::max(stair_height_, kMinObstacleHeightSteps);
    for (int s = 0; s < stair_steps_; ++s) {
      const double top = y_ + (s * stair_height_ * stair_dir_) * ts;
      boxes.push_back({ObstacleKind::kStair, x + (s * stair_width_) * ts, x + ((1 + s) * stair_width_) * ts,
                       top - box_h * ts, top});
    }
    counter_ = stair_steps_ * stair_width_ + 1;
    features.push_back({ObstacleKind::kStair, i, double(stair_width_), stair_height_, stair_steps_, stair_dir_});
  }

  void on_stairs() {
    const int s = stair_steps_ * stair_width_ - counter_;
    const int n = s / stair_width_;
    y_ = original_y_ + (n * stair_height_ * stair_dir_) * ts - (stair_dir_ == -1 ? stair_height_ : 0.0) * ts;
  }

  // the count ran out: grass for a while, and after grass one of the present obstacles
  void next_state() {
    counter_ = static_cast<int>(rng_.uniform_int(kTerrainGrass / 2, kTerrainGrass));
    if (state_ == State::kGrass && !present_.empty()) {
      state_ = present_[rng_.uniform_int(1, static_cast<int64_t>(present_.size()) + 1) - 1];
    } else {
      state_ = State::kGrass;
    }
    oneshot_ = true;
  }

  const EnvEncoding& e_;
  RandomStream& rng_;
  const std::vector<State> present_;
  State state_ = State::kGrass;
  double velocity_ = 0.0;
  double y_ = kTerrainHeight;
  int counter_ = kTerrainStartpad;
  bool oneshot_ = false;
  double original_y_ = 0;
  double pit_diff_ = 0;
  double stair_height_ = 0;
  int stair_dir_ = 1, stair_width_ = 0, stair_steps_ = 0;
};

}  // namespace

Terrain Terrain::generate(const EnvDef& def) {
  const EnvEncoding& e = def.encoding;
  if (auto err = validate(e)) throw std::invalid_argument("invalid environment: " + *err);
  if (def.seed >= kMaxEnvSeed) throw std::invalid_argument("invalid environment: seed must be < 1000000");

  RandomStream rng(stream_key(def.seed, "terrain"));
  Terrain t;
  if (e.is_cppn()) {
    const std::vector<double> relief = cppn_relief(*e.cppn);
    t.ground_.reserve(kTerrainLength);
    for (int i = 0; i < kTerrainLength; ++i) t.ground_.push_back({i * kTerrainStep, kTerrainHeight + relief[i]});
  } else {
    CourseWalk walk(e, rng);
    for (int i = 0; i < kTerrainLength; ++i) walk.step(i);
    t.ground_ = std::move(walk.ground);
    t.boxes_ = std::move(walk.boxes);
    t.features_ = std::move(walk.features);
  }
  t.push_unit_ = rng.uniform01();
  return t;
}

}  // namespace poet
