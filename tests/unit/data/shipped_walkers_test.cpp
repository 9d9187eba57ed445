// The walkers POET found and this project ships (data/walkers/shipped.json, written by experiments/ship_walker.sh):
// each still finishes its course on every terrain seed the manifest names, with the score of a solve (≥ 230), so a
// change to the simulation that breaks them is seen here.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/formats/envgen/env_json.h"
#include "common/formats/policy/policy_file.h"
#include "simulation/envgen/env_distance.h"
#include "simulation/rollout_task.h"
#include "walker_manifest.h"

namespace poet {
namespace {

TEST(ShippedWalkers, EachFinishesItsCourseOnTheSeedsTheManifestNames) {
  const std::vector<test::ManifestWalker> manifest = test::read_walker_manifest("shipped.json");
  ASSERT_FALSE(manifest.empty()) << "data/walkers/shipped.json is missing or empty";
  for (const auto& [name, entry, walker] : manifest) {
    ASSERT_TRUE(walker) << name << ": " << walker.error();
    const Expected<EnvDef> env = load_env_def(test::kSourceRoot + "/" + entry.at("environment").get<std::string>());
    ASSERT_TRUE(env) << name << ": " << env.error();
    EXPECT_NE(difficulty(env->encoding), Difficulty::kEasy) << name << " is shipped as challenging or above";
    auto theta = std::make_shared<const std::vector<double>>(walker->params);
    const std::vector<uint32_t> seeds = entry.at("finishes_on_seeds");
    ASSERT_FALSE(seeds.empty()) << name;
    EXPECT_NE(std::find(seeds.begin(), seeds.end(), env->seed), seeds.end()) << name << ": its own course";
    for (uint32_t seed : seeds) {
      RolloutTask task;
      task.theta = theta;
      task.env = EnvDef{env->encoding, seed};
      const RolloutResult r = run_task(task);
      EXPECT_TRUE(r.finished) << name << " on terrain seed " << seed << ": return " << r.total_reward;
      if (seed == env->seed) {
        EXPECT_GE(r.total_reward, 230) << name << " on its own course";
      }
    }
  }
}

}  // namespace
}  // namespace poet
