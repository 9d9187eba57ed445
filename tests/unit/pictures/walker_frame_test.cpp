// Tests pictures/walker_frame.cpp: a frame is width × height RGB with the sky, the ground and the walker in it,
// follows the walker as it moves, and options out of range are errors, not pictures.

#include "pictures/walker_frame.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

std::set<std::tuple<int, int, int>> colours(const FrameImage& image) {
  std::set<std::tuple<int, int, int>> out;
  for (size_t i = 0; i + 2 < image.rgb.size(); i += 3) out.insert({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
  return out;
}

TEST(WalkerFrame, ShowsTheCourseAndTheWalkerWhereItIs) {
  const Terrain terrain = Terrain::generate({named_course("hardcore-like").value(), 3});
  WalkerEnv env(terrain);
  env.reset();
  const Expected<FrameImage> start = render_walker_frame(terrain, env.pose(), {.width = 200, .height = 120});
  ASSERT_TRUE(start) << start.error();
  EXPECT_EQ(start->width, 200);
  EXPECT_EQ(start->height, 120);
  ASSERT_EQ(start->rgb.size(), 200u * 120u * 3u);
  EXPECT_GE(colours(*start).size(), 4u);  // sky, ground, hull, legs at least
  EXPECT_EQ(render_walker_frame(terrain, env.pose(), {.width = 200, .height = 120})->rgb, start->rgb);
  for (int k = 0; k < 120; ++k) env.step({0.5, -0.5, 0.5, -0.5});
  EXPECT_NE(render_walker_frame(terrain, env.pose(), {.width = 200, .height = 120})->rgb, start->rgb);
}

TEST(WalkerFrame, OptionsOutOfRangeAreErrors) {
  const Terrain terrain = Terrain::generate({named_course("flat").value(), 0});
  WalkerEnv env(terrain);
  env.reset();
  EXPECT_FALSE(render_walker_frame(terrain, env.pose(), {.width = 8}));
  EXPECT_FALSE(render_walker_frame(terrain, env.pose(), {.height = 5000}));
  const Expected<FrameImage> bad = render_walker_frame(terrain, env.pose(), {.pixels_per_metre = 0});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("pixels_per_metre"), std::string::npos);
}

}  // namespace
}  // namespace poet
