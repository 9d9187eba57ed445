#include "simulation/walker/terrain.h"

#include <gtest/gtest.h>

#include <cmath>

#include "simulation/rng.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

using namespace walker;

EnvDef make_def(EnvEncoding e, uint32_t seed) { return EnvDef{std::move(e), seed}; }

// A random valid encoding with every obstacle type, drawn from wide intervals.
EnvEncoding random_encoding(RandomStream& rng) {
  auto real = [&](double max) {
    const double a = rng.uniform(0, max), b = rng.uniform(0, max);
    return Interval{std::min(a, b), std::max(a, b)};
  };
  auto integer = [&](int lo_min, int lo_max, int span_max) {
    const double lo = double(rng.uniform_int(lo_min, lo_max + 1));
    return Interval{lo, lo + double(rng.uniform_int(1, span_max + 1))};
  };
  EnvEncoding e;
  e.roughness = rng.uniform(0, 10);
  if (rng.uniform01() < 0.8) e.pit_gap = real(8);
  if (rng.uniform01() < 0.8) {
    e.stump_width = integer(1, 2, 2);
    e.stump_height = real(5);
    e.stump_float = integer(0, 1, 1);
  }
  if (rng.uniform01() < 0.8) {
    e.stair_height = real(5);
    e.stair_width = integer(1, 5, 2);
    e.stair_steps = integer(1, 5, 4);
  }
  return e;
}

bool inside(double v, const Interval& iv) { return v >= iv.lo && (v < iv.hi || iv.lo == iv.hi); }

TEST(Terrain, FlatCourseIsLevelWithNoObstacles) {
  const Terrain t = Terrain::generate(make_def(EnvEncoding{}, 123));
  ASSERT_EQ(t.ground().size(), size_t(kTerrainLength));
  for (int i = 0; i < kTerrainLength; ++i) {
    EXPECT_DOUBLE_EQ(t.ground()[i].x, i * kTerrainStep);
    EXPECT_DOUBLE_EQ(t.ground()[i].y, kTerrainHeight);
  }
  EXPECT_TRUE(t.boxes().empty());
  EXPECT_TRUE(t.features().empty());
}

TEST(Terrain, SameDefinitionGivesTheSameCourseAndSeedsDiffer) {
  RandomStream rng(stream_key(5, "test"));
  for (int n = 0; n < 50; ++n) {
    const EnvDef def = make_def(random_encoding(rng), uint32_t(rng.uniform_int(0, kMaxEnvSeed)));
    const Terrain a = Terrain::generate(def), b = Terrain::generate(def);
    ASSERT_EQ(a.boxes().size(), b.boxes().size());
    for (size_t i = 0; i < a.ground().size(); ++i) {
      ASSERT_EQ(a.ground()[i].x, b.ground()[i].x);
      ASSERT_EQ(a.ground()[i].y, b.ground()[i].y);
    }
    for (size_t i = 0; i < a.boxes().size(); ++i) {
      ASSERT_EQ(a.boxes()[i].x0, b.boxes()[i].x0);
      ASSERT_EQ(a.boxes()[i].y1, b.boxes()[i].y1);
    }
    EXPECT_EQ(a.push_unit(), b.push_unit());
  }
  EnvEncoding rough;
  rough.roughness = 1;
  EXPECT_NE(Terrain::generate(make_def(rough, 1)).ground()[100].y,
            Terrain::generate(make_def(rough, 2)).ground()[100].y);
}

TEST(Terrain, PureRoughnessScalesOneProfileLinearly) {
  EnvEncoding r1, r3;
  r1.roughness = 1;
  r3.roughness = 3;
  const Terrain a = Terrain::generate(make_def(r1, 77)), b = Terrain::generate(make_def(r3, 77));
  for (int i = 0; i < kTerrainLength; ++i)
    EXPECT_NEAR(b.ground()[i].y - kTerrainHeight, 3 * (a.ground()[i].y - kTerrainHeight), 1e-9) << i;
  // The start pad (points up to 20) draws nothing: it stays level.
  for (int i = 0; i <= kTerrainStartpad; ++i) EXPECT_DOUBLE_EQ(b.ground()[i].y, kTerrainHeight);
}

TEST(Terrain, ObstacleSizesStayInsideTheirSampledIntervals) {
  RandomStream rng(stream_key(9, "test"));
  int pits = 0, stumps = 0, stairs = 0;
  for (int n = 0; n < 400; ++n) {
    const EnvEncoding e = random_encoding(rng);
    const Terrain t = Terrain::generate(make_def(e, uint32_t(n)));
    const bool any = e.has_pits() || e.has_stumps() || e.has_stairs();
    ASSERT_EQ(!t.features().empty(), any);
    if (any) {
      EXPECT_EQ(t.features().front().point_index, kTerrainStartpad);  // first obstacle after the pad
    }
    for (const ObstacleFeature& f : t.features()) {
      switch (f.kind) {
        case ObstacleKind::kPitWall:
          ++pits;
          ASSERT_TRUE(e.has_pits());
          EXPECT_TRUE(inside(f.width - 1.0, *e.pit_gap)) << f.width;
          EXPECT_EQ(f.height, kPitDepthSteps);
          break;
        case ObstacleKind::kStump:
          ++stumps;
          ASSERT_TRUE(e.has_stumps());
          EXPECT_TRUE(inside(f.height, *e.stump_height)) << f.height;
          EXPECT_TRUE(inside(f.width, *e.stump_width)) << f.width;
          EXPECT_LT(f.width, e.stump_width->hi);
          break;
        case ObstacleKind::kStair:
          ++stairs;
          ASSERT_TRUE(e.has_stairs());
          EXPECT_TRUE(inside(f.height, *e.stair_height)) << f.height;
          EXPECT_GE(f.steps, e.stair_steps->lo);
          EXPECT_LT(f.steps, e.stair_steps->hi);
          EXPECT_GE(f.width, e.stair_width->lo);
          EXPECT_LT(f.width, e.stair_width->hi);
          EXPECT_TRUE(f.direction == 1 || f.direction == -1);
          break;
      }
    }
    for (const TerrainBox& b : t.boxes()) {
      EXPECT_GE(b.y1 - b.y0, kMinObstacleHeightSteps * kTerrainStep * (1 - 1e-9));  // buildable in Box2D
      EXPECT_GE(b.x1 - b.x0, kTerrainStep * (1 - 1e-9));
    }
    for (size_t i = 1; i < t.ground().size(); ++i) ASSERT_GT(t.ground()[i].x, t.ground()[i - 1].x);
  }
  EXPECT_GT(pits, 100);
  EXPECT_GT(stumps, 100);
  EXPECT_GT(stairs, 100);
}

TEST(Terrain, PitOpeningIsTheSampledGap) {
  EnvEncoding e;
  e.pit_gap = Interval{2, 4};
  const Terrain t = Terrain::generate(make_def(e, 4));
  ASSERT_GE(t.boxes().size(), 2u);
  const TerrainBox& near = t.boxes()[0];
  const TerrainBox& far = t.boxes()[1];
  const double opening = (far.x0 - near.x1) / kTerrainStep;
  EXPECT_NEAR(opening, t.features()[0].width - 1.0, 1e-9);
  EXPECT_GE(opening, 2.0);
  EXPECT_LT(opening, 4.0);
  EXPECT_NEAR(near.y1 - near.y0, 4 * kTerrainStep, 1e-12);
}

TEST(Terrain, NearZeroObstacleHeightsAreClampedNotDropped) {
  EnvEncoding e;
  e.stump_width = Interval{1, 2};
  e.stump_height = Interval{0, 0};
  e.stump_float = Interval{0, 1};
  const Terrain t = Terrain::generate(make_def(e, 1));
  ASSERT_FALSE(t.boxes().empty());
  for (const TerrainBox& b : t.boxes()) EXPECT_NEAR(b.y1 - b.y0, kMinObstacleHeightSteps * kTerrainStep, 1e-12);
  for (const ObstacleFeature& f : t.features()) EXPECT_EQ(f.height, 0.0);
}

TEST(Terrain, RejectsInvalidDefinitions) {
  EnvEncoding bad;
  bad.roughness = std::nan("");
  EXPECT_THROW(Terrain::generate(make_def(bad, 0)), std::invalid_argument);
  EnvEncoding inverted;
  inverted.pit_gap = Interval{3, 1};
  EXPECT_THROW(Terrain::generate(make_def(inverted, 0)), std::invalid_argument);
  EXPECT_THROW(Terrain::generate(make_def(EnvEncoding{}, kMaxEnvSeed)), std::invalid_argument);
}

}  // namespace
}  // namespace poet
