#include "tests/support/test_worker/lie_shape.h"

#include <gtest/gtest.h>

#include "simulation/rng.h"

namespace poet::test_worker {
namespace {

double unit(uint64_t key) { return static_cast<double>(key >> 11) * 0x1.0p-53; }

TEST(LieShape, ByDefaultEveryAnswerIsALie) {
  Liar liar{LieShape{}};
  for (uint64_t job = 1; job <= 20; ++job) EXPECT_TRUE(liar.lies_on(job, 3));
}

TEST(LieShape, HonestJobsComeFirstThenTheFractionDrawnFromTheJobId) {
  Liar liar{LieShape{.honest_jobs = 5, .fraction = 0.3}};
  for (uint64_t job = 1; job <= 5; ++job) EXPECT_FALSE(liar.lies_on(job, 1)) << job;
  int lies = 0;
  for (uint64_t job = 6; job < 1006; ++job) {
    const bool lie = liar.lies_on(job, 1);
    EXPECT_EQ(lie, unit(stream_key(0, "lie", {job})) < 0.3) << job;
    lies += lie ? 1 : 0;
  }
  EXPECT_NEAR(lies, 300, 60);
}

TEST(LieShape, WherePredictedUncheckedLiesOnlyWhereThePublicRuleDrawsNoCheck) {
  Liar liar{LieShape{.where_predicted_unchecked = true}};
  int spared = 0;
  for (uint64_t job = 1; job <= 1000; ++job) {
    const bool checked = unit(stream_key(1, "verify", {7, job})) < 0.05;
    EXPECT_EQ(liar.lies_on(job, 7), !checked) << job;
    spared += checked ? 1 : 0;
  }
  EXPECT_GT(spared, 0);
}

}  // namespace
}  // namespace poet::test_worker
