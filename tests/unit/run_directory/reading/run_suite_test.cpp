// Tests run_directory/reading/run_suite.cpp: a run's candidates are every pair's θ and its best θ where it differs;
// the best agent, overall and per group, is the most finished, then the further mean progress, then the higher mean
// return, the earlier candidate on a tie; a θ that several candidates hold is run once.

#include "run_directory/reading/run_suite.h"

#include <gtest/gtest.h>

#include "common/formats/policy/policy_file.h"

namespace poet {
namespace {

TEST(RunSuite, CandidatesAreEachPairsThetaAndItsBestThetaWhereItDiffers) {
  RunState state;
  Pair a, b;
  a.id = 0;
  a.theta = {1, 2};
  a.best_theta = {1, 2};
  b.id = 3;
  b.theta = {1, 2};
  b.best_theta = {3, 4};
  b.retired_iteration = 5;  // retired pairs are candidates too
  state.pairs = {a, b};
  const std::vector<SuiteCandidate> c = suite_candidates(state);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].label, "pair 0");
  EXPECT_EQ(c[1].label, "pair 3");
  EXPECT_EQ(c[2].label, "pair 3 best");
  EXPECT_TRUE(c[2].best_theta);
  EXPECT_EQ(c[2].theta, b.best_theta);
}

TEST(RunSuite, TheWalkerThatGoesFurtherIsBestAndTheTableAndJsonSaySo) {
  const Expected<PolicyFile> walker = load_policy(std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json");
  ASSERT_TRUE(walker) << walker.error();
  RunState state;
  state.settings.episodes.max_steps = 2000;
  Pair random, flat, copy;
  random.id = 0;
  random.theta = std::vector<double>(walker->params.size(), 0.0);
  flat.id = 1;
  flat.theta = walker->params;
  copy.id = 2;
  copy.theta = walker->params;  // as a transfer leaves it: the same θ as pair 1
  state.pairs = {random, flat, copy};
  // the hardcore-like group and the easy courses are where the flat walker can get anywhere
  const CourseSuite suite = make_suite("small", 11, 3, 1);
  const RunSuite run = evaluate_run_on_suite(state, suite, 2);
  ASSERT_EQ(run.scores.size(), 3u);
  EXPECT_EQ(run.best, 1u) << "the flat walker, and of its two holders the earlier";
  EXPECT_EQ(run.scores[2].groups[0].episodes.size(), 3u);
  EXPECT_EQ(run.scores[2].mean_return(), run.scores[1].mean_return());
  const size_t hardcore = 4;
  EXPECT_EQ(run.best_per_group[hardcore], 1u) << "the flat walker goes further on hardcore-like than θ = 0";
  EXPECT_GT(run.scores[1].groups[hardcore].mean_progress(), run.scores[0].groups[hardcore].mean_progress());
  const std::string table = run_suite_table(run);
  EXPECT_NE(table.find("best on hardcore-like: pair 1"), std::string::npos) << table;
  const nlohmann::json j = run_suite_json(run, suite, "somewhere", false);
  EXPECT_EQ(j["best_per_group"]["hardcore-like"], "pair 1");
  EXPECT_EQ(j["candidates"].size(), 3u);
  EXPECT_EQ(j["best"], "pair 1");
  EXPECT_EQ(j["run_dir"], "somewhere");
  EXPECT_EQ(run_suite_table(RunSuite{}), "the run has no agents to evaluate\n");
}

}  // namespace
}  // namespace poet
