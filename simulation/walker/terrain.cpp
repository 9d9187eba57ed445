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

}  // namespace

Terrain Terrain::generate(const EnvDef& def) {
  const EnvEncoding& e = def.encoding;
  if (auto err = validate(e)) throw std::invalid_argument("invalid environment: " + *err);
  if (def.seed >= kMaxEnvSeed) throw std::invalid_argument("invalid environment: seed must be < 1000000");

  std::vector<State> present;  // numbered 1.. in this order, as the reference does
  if (e.has_stumps()) present.push_back(State::kStump);
  if (e.has_stairs()) present.push_back(State::kStairs);
  if (e.has_pits()) present.push_back(State::kPit);

  RandomStream rng(stream_key(def.seed, "terrain"));
  Terrain t;
  t.ground_.reserve(kTerrainLength);
  const double ts = kTerrainStep;
  if (e.is_cppn()) {
    const std::vector<double> relief = cppn_relief(*e.cppn);
    for (int i = 0; i < kTerrainLength; ++i) t.ground_.push_back({i * ts, kTerrainHeight + relief[i]});
    t.push_unit_ = rng.uniform01();
    return t;
  }

  State state = State::kGrass;
  double velocity = 0.0;
  double y = kTerrainHeight;
  int counter = kTerrainStartpad;
  bool oneshot = false;
  double original_y = 0;
  double pit_diff = 0;
  double stair_height = 0;
  int stair_dir = 1, stair_width = 0, stair_steps = 0;

  for (int i = 0; i < kTerrainLength; ++i) {
    const double x = i * ts;
    t.ground_.push_back({x, 0});

    if (state == State::kGrass && !oneshot) {
      velocity = 0.8 * velocity + 0.01 * sign(kTerrainHeight - y);
      if (i > kTerrainStartpad) velocity += rng.uniform(-1, 1) / kScale;
      y += e.roughness * velocity;
    } else if (state == State::kPit && oneshot) {
      const double gap = rng.uniform(e.pit_gap->lo, e.pit_gap->hi);
      const double w = 1.0 + gap;  // wall to wall, in steps
      counter = static_cast<int>(std::ceil(w)) + 2;
      pit_diff = std::ceil(w) - w;
      original_y = y;
      const double depth = kPitDepthSteps * ts;
      t.boxes_.push_back({ObstacleKind::kPitWall, x, x + ts, y - depth, y});
      t.boxes_.push_back({ObstacleKind::kPitWall, x + w * ts, x + ts + w * ts, y - depth, y});
      t.features_.push_back({ObstacleKind::kPitWall, i, w, kPitDepthSteps});
    } else if (state == State::kPit && !oneshot) {
      y = original_y;
      if (counter > 1) y -= kPitDepthSteps * ts;
      if (counter == 1) {
        t.ground_.back().x -= pit_diff * ts;  // the far wall sits at a fractional step: keep the gap continuous
        pit_diff = 0;
      }
    } else if (state == State::kStump && oneshot) {
      const int width = static_cast<int>(randint(rng, *e.stump_width));
      const double height = rng.uniform(e.stump_height->lo, e.stump_height->hi);
      const int lift = static_cast<int>(randint(rng, *e.stump_float));
      counter = width;
      const double y0 = y + lift * ts;
      const double box_h = std::max(height, kMinObstacleHeightSteps);
      t.boxes_.push_back({ObstacleKind::kStump, x, x + width * ts, y0, y0 + box_h * ts});
      t.features_.push_back({ObstacleKind::kStump, i, double(width), height});
    } else if (state == State::kStairs && oneshot) {
      stair_height = rng.uniform(e.stair_height->lo, e.stair_height->hi);
      stair_dir = rng.uniform01() > 0.5 ? 1 : -1;
      stair_width = static_cast<int>(randint(rng, *e.stair_width));
      stair_steps = static_cast<int>(randint(rng, *e.stair_steps));
      original_y = y;
      const double box_h = std::max(stair_height, kMinObstacleHeightSteps);
      for (int s = 0; s < stair_steps; ++s) {
        const double top = y + (s * stair_height * stair_dir) * ts;
        t.boxes_.push_back({ObstacleKind::kStair, x + (s * stair_width) * ts, x + ((1 + s) * stair_width) * ts,
                            top - box_h * ts, top});
      }
      counter = stair_steps * stair_width + 1;
      t.features_.push_back({ObstacleKind::kStair, i, double(stair_width), stair_height, stair_steps, stair_dir});
    } else if (state == State::kStairs && !oneshot) {
      const int s = stair_steps * stair_width - counter;
      const int n = s / stair_width;
      y = original_y + (n * stair_height * stair_dir) * ts - (stair_dir == -1 ? stair_height : 0.0) * ts;
    }

    oneshot = false;
    t.ground_.back().y = y;
    counter -= 1;
    if (counter == 0) {
      counter = static_cast<int>(rng.uniform_int(kTerrainGrass / 2, kTerrainGrass));
      if (state == State::kGrass && !present.empty()) {
        state = present[rng.uniform_int(1, static_cast<int64_t>(present.size()) + 1) - 1];
      } else {
        state = State::kGrass;
      }
      oneshot = true;
    }
  }

  t.push_unit_ = rng.uniform01();
  return t;
}

}  // namespace poet
