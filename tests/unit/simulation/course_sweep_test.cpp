// Tests simulation/course_sweep.cpp: a sweep runs one episode per terrain seed and counts the outcomes.

#include "simulation/course_sweep.h"

#include <gtest/gtest.h>

#include "common/formats/policy/policy_file.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

TEST(CourseSweep, RunsOneEpisodePerSeedAndCountsTheOutcomes) {
  const Expected<PolicyFile> walker = load_policy(std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json");
  ASSERT_TRUE(walker) << walker.error();
  const Mlp policy(walker->params);
  const CourseSweep flat = sweep_course(policy, "flat", named_course("flat").value(), 3, 3, {}, 2000, 2);
  ASSERT_EQ(flat.episodes.size(), 3u);
  EXPECT_EQ(flat.finished(), 3);  // the walker that ships finishes flat on every seed
  EXPECT_EQ(flat.finished() + flat.fell() + flat.timed_out(), 3);

  // a time limit too short to finish: no seed finished, every episode timed out
  const CourseSweep cut = sweep_course(policy, "flat", named_course("flat").value(), 0, 2, {}, 50, 1);
  EXPECT_EQ(cut.timed_out(), 2);
  EXPECT_EQ(cut.finished(), 0);
}

}  // namespace
}  // namespace poet
