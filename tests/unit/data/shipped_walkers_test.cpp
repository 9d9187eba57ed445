// The walkers POET found and this project ships (data/walkers/shipped.json, written by experiments/ship_walker.sh):
// each still finishes its course on every terrain seed the manifest names, with the score of a solve (≥ 230), so a
// change to the simulation that breaks them is seen here.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "envgen/env_distance.h"
#include "envgen/env_json.h"
#include "policy/policy_file.h"
#include "rollout_task.h"

namespace poet {
namespace {

const std::string kRoot = POET_SOURCE_DIR;

TEST(ShippedWalkers, EachFinishesItsCourseOnTheSeedsTheManifestNames) {
  std::ifstream in(kRoot + "/data/walkers/shipped.json");
  ASSERT_TRUE(in) << "data/walkers/shipped.json is missing";
  const nlohmann::json manifest = nlohmann::json::parse(in);
  ASSERT_FALSE(manifest.empty());
  for (const nlohmann::json& entry : manifest) {
    const std::string name = entry.at("name");
    const Expected<PolicyFile> walker = load_policy(kRoot + "/" + entry.at("walker").get<std::string>());
    ASSERT_TRUE(walker) << name << ": " << walker.error();
    const Expected<EnvDef> env = load_env_def(kRoot + "/" + entry.at("environment").get<std::string>());
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
