#pragma once
// The geometry of one course, generated from an environment definition (spec §1.2). It is computed once per
// (encoding, seed) and shared read-only by every episode on that course; each episode builds a fresh Box2D
// world from it, so a rollout never depends on what ran before.

#include <cstdint>
#include <vector>

#include "simulation/envgen/env_encoding.h"

namespace poet {

struct Point {
  double x = 0;
  double y = 0;
};

enum class ObstacleKind { kPitWall, kStump, kStair };

// An axis-aligned static box, world metres.
struct TerrainBox {
  ObstacleKind kind;
  double x0, x1, y0, y1;
};

// One obstacle as sampled (sizes in terrain steps, before any thickness clamp): for analysis and statistics.
struct ObstacleFeature {
  ObstacleKind kind;
  int point_index;    // terrain point where it starts
  double width;       // pit: 1 + gap (wall to wall), stump: width, stair: width of one step
  double height;      // pit: depth, stump: height, stair: rise of one step
  int steps = 1;      // stairs: step count
  int direction = 0;  // stairs: +1 up, -1 down
};

class Terrain {
 public:
  // Draws the course for a valid definition (see validate()); throws std::invalid_argument otherwise. A CPPN
  // course's ground is kTerrainHeight plus cppn_relief(), with no boxes; its seed draws only the push.
  static Terrain generate(const EnvDef& def);

  const std::vector<Point>& ground() const { return ground_; }     // kTerrainLength points, left to right
  const std::vector<TerrainBox>& boxes() const { return boxes_; }  // in generation order
  const std::vector<ObstacleFeature>& features() const { return features_; }
  // The initial push is F = push_scale · (2u − 1) with u ~ U[0, 1) drawn right after the terrain draws.
  double push_unit() const { return push_unit_; }
  double push_force(double push_scale) const { return -push_scale + 2.0 * push_scale * push_unit_; }

 private:
  std::vector<Point> ground_;
  std::vector<TerrainBox> boxes_;
  std::vector<ObstacleFeature> features_;
  double push_unit_ = 0.5;
};

}  // namespace poet
