// Distribution statistics of this project's courses and random initial policies over terrain seeds 0..49, against
// the reference walker's figures (reference/STATISTICS.md, quoted here so the checks run without the data).

#include "simulation/course_statistics.h"

#include <gtest/gtest.h>

#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

TEST(CourseStatistics, RoughnessScalesMeanSlopeLikeReference) {
  for (double r : {1.0, 3.0}) {
    EnvEncoding e;
    e.roughness = r;
    const double reference = 0.02045 * r;  // mean |Δy| = 0.02045·r in the reference
    EXPECT_NEAR(terrain_statistics(e, 0, 50).mean_abs_dy, reference, 0.05 * reference) << "roughness " << r;
  }
}

TEST(CourseStatistics, ObstacleCountsAndSizesMatchReference) {
  const TerrainStatistics hard = terrain_statistics(*named_course("hard"), 0, 50);
  EXPECT_NEAR(hard.obstacles, 17.16, 0.1 * 17.16);
  EXPECT_NEAR(hard.pits, 9.04, 0.1 * 9.04);
  EXPECT_NEAR(hard.stumps, 8.12, 0.1 * 8.12);
  EXPECT_EQ(hard.stairs, 0);
  EXPECT_NEAR(hard.mean_pit_width, 3.991, 0.1);  // 1 + U(2, 4)
  EXPECT_NEAR(hard.mean_stump_height, 2.010, 0.1);

  const TerrainStatistics like = terrain_statistics(*named_course("hardcore-like"), 0, 50);
  EXPECT_NEAR(like.obstacles, 13.16, 0.1 * 13.16);
  EXPECT_NEAR(like.mean_pit_width, 3.048, 0.1);
  EXPECT_NEAR(like.mean_stump_height, 1.229, 0.1);
  // the kind of each obstacle is a uniform draw among three: each about a third of the obstacles
  for (double kind : {like.pits, like.stumps, like.stairs})
    EXPECT_NEAR(kind, like.obstacles / 3, 0.2 * like.obstacles / 3);
}

TEST(CourseStatistics, RandomInitialPoliciesBehaveLikeReference) {
  struct Ref {
    const char* course;
    double fell;
  };
  // median return −94.0 and median steps 126–130 on every course; fell fractions per course
  for (const Ref& ref : {Ref{"flat", 0.645}, Ref{"r3", 0.650}, Ref{"hardcore-like", 0.640}}) {
    const RandomPolicyStatistics s = random_policy_statistics(*named_course(ref.course), 200, 1, {}, 2);
    EXPECT_NEAR(s.median_return, -94.0, 9.4) << ref.course;
    EXPECT_NEAR(s.fell, ref.fell, 0.08) << ref.course;
    EXPECT_NEAR(s.median_steps, 127, 0.15 * 127) << ref.course;
    EXPECT_EQ(s.finished, 0) << ref.course;
  }
}

}  // namespace
}  // namespace poet
