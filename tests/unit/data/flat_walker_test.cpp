// The shipped walker (data/walkers/flat-walker.json) solves the flat course: it finishes on at least 45 of 50
// terrain seeds with a mean score of at least 230, and walks a rough course of roughness 1 too.

#include <gtest/gtest.h>

#include "common/formats/policy/policy_file.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/rollout_task.h"

namespace poet {
namespace {

struct Sweep {
  int finished = 0;
  double mean = 0;
};

Sweep sweep(const std::vector<double>& theta, const std::string& course) {
  auto shared = std::make_shared<const std::vector<double>>(theta);
  Sweep out;
  constexpr int kSeeds = 50;
  for (uint32_t seed = 0; seed < kSeeds; ++seed) {
    RolloutTask task;
    task.theta = shared;
    task.env = EnvDef{named_course(course).value(), seed};
    const RolloutResult r = run_task(task);
    out.finished += r.finished ? 1 : 0;
    out.mean += r.total_reward / kSeeds;
  }
  return out;
}

TEST(FlatWalker, FinishesTheFlatCourseOnAlmostEverySeed) {
  const Expected<PolicyFile> walker = load_policy(std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json");
  ASSERT_TRUE(walker) << walker.error();
  const Sweep flat = sweep(walker->params, "flat");
  EXPECT_GE(flat.finished, 45);
  EXPECT_GE(flat.mean, 230);
  const Sweep rough = sweep(walker->params, "r1");
  EXPECT_GE(rough.finished, 45);
}

}  // namespace
}  // namespace poet
