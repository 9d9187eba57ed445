#include "simulation/envgen/cppn_course.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

using namespace walker;

TEST(CppnCourse, XRunsOverMinusPiToPi) {
  EXPECT_DOUBLE_EQ(cppn_course_x(0), -std::numbers::pi);
  EXPECT_NEAR(cppn_course_x(kTerrainLength / 2), 0.0, 1e-15);
  EXPECT_NEAR(cppn_course_x(1) - cppn_course_x(0), std::numbers::pi / 100, 1e-15);  // 200 points over 2π
}

TEST(CppnCourse, ReliefIsFlatOnThePadAndRelativeAfterIt) {
  // out = 0.5·x′ + 0.2: relief_i = 0.5·(x′_i − x′_21) beyond the pad
  const std::vector<double> relief = cppn_relief(cppn_seed_genome(0.5, 0.2));
  ASSERT_EQ(relief.size(), static_cast<size_t>(kTerrainLength));
  for (int i = 0; i <= kTerrainStartpad + 1; ++i) EXPECT_EQ(relief[i], 0.0) << i;
  EXPECT_NEAR(relief[kTerrainStartpad + 2], 0.5 * std::numbers::pi / 100, 1e-12);
  EXPECT_NEAR(relief[kTerrainLength - 1], 0.5 * (kTerrainLength - 1 - 21) * std::numbers::pi / 100, 1e-12);
}

TEST(CppnCourse, TerrainGroundIsTheReliefOverTheStartHeight) {
  EnvDef def;
  def.encoding.cppn = std::make_shared<const CppnGenome>(cppn_seed_genome(-0.5, 0.0));
  def.encoding.name = cppn_name(*def.encoding.cppn);
  def.seed = 7;
  const Terrain t = Terrain::generate(def);
  ASSERT_EQ(t.ground().size(), static_cast<size_t>(kTerrainLength));
  EXPECT_TRUE(t.boxes().empty());
  EXPECT_EQ(t.ground()[0].y, kTerrainHeight);
  EXPECT_EQ(t.ground()[21].y, kTerrainHeight);
  EXPECT_NEAR(t.ground()[121].y, kTerrainHeight - 0.5 * std::numbers::pi, 1e-12);  // 100 points on: x′ + π
  EXPECT_DOUBLE_EQ(t.ground()[121].x, 121 * kTerrainStep);
  // the seed draws the push, and only the push
  def.seed = 8;
  const Terrain other = Terrain::generate(def);
  EXPECT_EQ(other.ground()[121].y, t.ground()[121].y);
  EXPECT_NE(other.push_unit(), t.push_unit());
}

TEST(CppnCourse, AReliefBeyondTheBoundIsRefused) {
  CppnGenome steep = cppn_seed_genome(10.0, 0.0);
  EXPECT_FALSE(validate_cppn_course(steep));  // 10 · 2π < 100 m
  steep.scale = 2.0;
  EXPECT_EQ(validate_cppn_course(steep).value_or(""),
            "cppn: the course's ground leaves ±100 m of the start pad (or overflows)");
  EnvEncoding e;
  e.cppn = std::make_shared<const CppnGenome>(steep);
  EXPECT_TRUE(validate(e));
  e.cppn = std::make_shared<const CppnGenome>(cppn_seed_genome(1.0, 0.0));
  e.roughness = 1.0;
  EXPECT_EQ(validate(e).value_or(""), "cppn: a CPPN course has ground_roughness 0 and no obstacle intervals");
}

}  // namespace
}  // namespace poet
