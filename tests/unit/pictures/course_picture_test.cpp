#include "pictures/course_picture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scratch_dir.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

class CoursePicture : public ::testing::Test {
 protected:
  poet::testing::ScratchDir scratch_;
  std::filesystem::path dir_ = scratch_.path();
};

TEST_F(CoursePicture, SvgShowsEveryObstacleAndThePath) {
  const Terrain t = Terrain::generate({*named_course("hardcore-like"), 1});
  const RolloutResult r = rollout(Mlp(zero_params()), t, {}, {.max_steps = 60, .record_trajectory = true});
  const auto path = (dir_ / "course.svg").string();
  ASSERT_EQ(write_course_picture(path, t, r), "");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string svg = text.str();
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  // every obstacle box is one filled path in its kind's colour
  auto count = [&](const std::string& needle) {
    size_t n = 0;
    for (size_t pos = 0; (pos = svg.find(needle, pos)) != std::string::npos; ++pos) ++n;
    return n;
  };
  size_t kinds[3] = {0, 0, 0};
  for (const TerrainBox& b : t.boxes()) ++kinds[static_cast<int>(b.kind)];
  ASSERT_GT(kinds[0] * kinds[1] * kinds[2], 0u);  // this course has pits, stumps and stairs
  EXPECT_EQ(count("fill:rgb(60%,60%,60%)"), kinds[static_cast<int>(ObstacleKind::kPitWall)]);
  EXPECT_EQ(count("fill:rgb(55%,35%,20%)"), kinds[static_cast<int>(ObstacleKind::kStump)]);
  EXPECT_EQ(count("fill:rgb(45%,50%,60%)"), kinds[static_cast<int>(ObstacleKind::kStair)]);
  // the hull: a faded snapshot every 50 steps (poses 0 and 50 of 61) and the final pose
  EXPECT_EQ(count("fill:rgb(50%,40%,90%)"), 3u);
}

TEST_F(CoursePicture, PngAndErrors) {
  const Terrain t = Terrain::generate({*named_course("flat"), 1});
  const RolloutResult r = rollout(Mlp(zero_params()), t, {}, {.max_steps = 5, .record_trajectory = true});
  const auto png = (dir_ / "course.png").string();
  ASSERT_EQ(write_course_picture(png, t, r), "");
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  EXPECT_NE(write_course_picture((dir_ / "missing" / "x.svg").string(), t, r), "");
  EXPECT_NE(write_course_picture((dir_ / "y.svg").string(), t, r, {.pixels_per_metre = -1}), "");
}

}  // namespace
}  // namespace poet
