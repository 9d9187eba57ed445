#include "run_directory/reading/coverage.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(Coverage, SampleIsSeededAndEachSampleIsAtItsLevelInTheBox) {
  const std::vector<CoverageSample> a = coverage_sample(5, 200);
  ASSERT_EQ(a.size(), 600u);
  for (size_t i = 0; i < a.size(); ++i) {
    const CoverageSample& s = a[i];
    EXPECT_EQ(s.level, static_cast<int>(i / 200) + 1);
    EXPECT_EQ(static_cast<int>(difficulty(s.e)), s.level);
    for (size_t k = 0; k < 5; ++k) {
      EXPECT_GE(s.e[k], 0);
      EXPECT_LE(s.e[k], kEnvVectorMax[k]);
    }
    EXPECT_LE(s.e[1], s.e[2]);
    EXPECT_LE(s.e[3], s.e[4]);
  }
  const std::vector<CoverageSample> b = coverage_sample(5, 200);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].e, b[i].e);
  EXPECT_NE(coverage_sample(6, 200)[0].e, a[0].e);
}

TEST(Coverage, DistanceToNearestSolvedEnvironmentAtChallengingOrAbove) {
  RunState state;
  Pair easy, hard, unsolved;
  easy.id = 0;
  easy.first_solved_iteration = 1;  // solved but easy: not a reference
  hard.id = 1;
  hard.env.encoding.roughness = 6;
  hard.first_solved_iteration = 5;
  unsolved.id = 2;
  unsolved.env.encoding.roughness = 8;
  state.pairs = {easy, hard, unsolved};
  const Coverage c = compute_coverage(state, 5, 100);
  ASSERT_EQ(c.solved.size(), 1u);
  double sum = 0;
  for (const CoverageSample& s : c.samples) {
    ASSERT_TRUE(s.distance);
    EXPECT_DOUBLE_EQ(*s.distance, normalized_distance(s.e, EnvVector{6, 0, 0, 0, 0}));
    if (s.level == 1) sum += *s.distance;
  }
  ASSERT_TRUE(c.sum[0]);
  EXPECT_DOUBLE_EQ(*c.sum[0], sum);

  state.pairs = {easy, unsolved};
  const Coverage none = compute_coverage(state, 5, 10);
  EXPECT_TRUE(none.solved.empty());
  EXPECT_FALSE(none.sum[0]);
  for (const CoverageSample& s : none.samples) EXPECT_FALSE(s.distance);
}

}  // namespace
}  // namespace poet
