// Tests common/formats/suite_score_json.cpp and suite_score_table.cpp: the JSON holds every episode under its course
// and seed with the group's figures; the tables print a line per group and per policy.

#include "common/formats/suite_score_json.h"

#include <gtest/gtest.h>

#include "common/formats/policy/policy_file.h"
#include "common/formats/suite_score_table.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

TEST(SuiteScoreJson, EveryEpisodeUnderItsCourseAndSeedWithTheGroupsFigures) {
  const Expected<PolicyFile> walker = load_policy(std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json");
  ASSERT_TRUE(walker) << walker.error();
  const CourseSuite suite = make_suite("small", 3, 2, 3);
  const SuiteScore score = run_suite(Mlp(walker->params), suite, {}, 80, 2);
  const nlohmann::json j = to_json(score, suite);
  EXPECT_EQ(j["suite"], "small");
  EXPECT_EQ(j["episodes"], 30);
  ASSERT_EQ(j["groups"].size(), 5u);
  for (size_t g = 0; g < 5; ++g) {
    const nlohmann::json& group = j["groups"][g];
    EXPECT_EQ(group["group"], suite.groups[g].name);
    EXPECT_EQ(group["episodes"], 6);
    EXPECT_EQ(group["mean_return"].get<double>(), score.groups[g].mean_return());
    EXPECT_EQ(group["finished_interval"][1].get<double>(), score.groups[g].finished_interval().second);
    size_t next = 0;
    for (size_t c = 0; c < suite.groups[g].courses.size(); ++c) {
      const nlohmann::json& course = group["courses"][c];
      EXPECT_EQ(course["course"], suite.groups[g].courses[c].encoding.name);
      for (size_t s = 0; s < suite.groups[g].courses[c].seeds.size(); ++s) {
        const RolloutResult& e = score.groups[g].episodes[next++];
        EXPECT_EQ(course["episodes"][s]["seed"], suite.groups[g].courses[c].seeds[s]);
        EXPECT_EQ(course["episodes"][s]["return"].get<double>(), e.total_reward);
        EXPECT_EQ(course["episodes"][s]["steps"], e.steps);
      }
    }
    EXPECT_EQ(next, 6u);
  }
  EXPECT_FALSE(summary_json(score)["groups"][0].contains("courses"));

  const std::string table = suite_table(score);
  EXPECT_NE(table.find("suite small: 30 episodes"), std::string::npos) << table;
  EXPECT_NE(table.find("\nhardcore-like "), std::string::npos) << table;
  const std::string row = suite_row("a policy", score);
  EXPECT_EQ(row.rfind("a policy", 0), 0u);
  EXPECT_NE(row.find(" of 30 "), std::string::npos) << row;
  EXPECT_NE(suite_rows_header(score).find("extremely"), std::string::npos);
}

}  // namespace
}  // namespace poet
