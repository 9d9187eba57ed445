// Tests run_directory/reading/goal_switching.cpp: the chain from the first environment down to a pair, and what solved
// each link (admission θ, own ES step, accepted transfer), read from the events' order.

#include "run_directory/reading/goal_switching.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

Pair pair(int id, double roughness, int created, int parent, int source, int solved) {
  Pair p;
  p.id = id;
  p.env.encoding.name = "r" + std::to_string(roughness);
  p.env.encoding.roughness = roughness;
  p.created_iteration = created;
  p.parent_id = parent;
  p.initial_source_pair = source;
  p.admission_score = 100 + id;
  p.first_solved_iteration = solved;
  return p;
}

nlohmann::json event(int iteration, const char* name, nlohmann::json fields) {
  fields["iteration"] = iteration;
  fields["event"] = name;
  return fields;
}

// flat (0) solved by its ES at 2; pair 1 (child of 0) admitted at 5 with θ from 0 and solved then; pair 2 (child
// of 1) admitted at 10 from pair 3's θ, solved at 15 by a transfer from pair 3; pair 3 (child of 0) unsolved.
RunSnapshot sample_run() {
  RunSnapshot run;
  run.state.next_iteration = 20;
  run.state.pairs = {pair(0, 0, 0, kNone, kNone, 2), pair(1, 1, 5, 0, 0, 5), pair(2, 5, 10, 1, 3, 15),
                     pair(3, 2, 8, 0, 0, kNone)};
  run.events = {event(2, "solved", {{"pair", 0}}),
                event(5, "pair_created", {{"pair", 1}}),
                event(5, "solved", {{"pair", 1}}),
                event(10, "pair_created", {{"pair", 2}}),
                event(12, "transfer",
                      {{"target", 2}, {"source", 1}, {"proposal", false}, {"score", 150.0}, {"previous_score", 120.0}}),
                event(15, "transfer",
                      {{"target", 1}, {"source", 2}, {"proposal", false}, {"score", 280.0}, {"previous_score", 270.0}}),
                event(15, "transfer",
                      {{"target", 2}, {"source", 3}, {"proposal", true}, {"score", 240.0}, {"previous_score", 170.0}}),
                event(15, "solved", {{"pair", 2}})};
  return run;
}

TEST(GoalSwitching, TheChainFromTheFirstEnvironmentAndWhatSolvedEachLink) {
  const RunSnapshot run = sample_run();
  const RunMetrics metrics = compute_run_metrics(run);
  const std::vector<LineageLink> chain = lineage_chain(run, metrics, 2);
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[0].pair, 0);
  EXPECT_EQ(chain[0].cause, SolveCause::kOwnEs);
  EXPECT_FALSE(chain[0].solved_through_transfer);

  EXPECT_EQ(chain[1].pair, 1);
  EXPECT_EQ(chain[1].cause, SolveCause::kAdmission);
  EXPECT_EQ(chain[1].solved_by, 0);
  EXPECT_FALSE(chain[1].solved_through_transfer);  // its parent's θ, and no transfer before its solve
  ASSERT_EQ(chain[1].transfers_in.size(), 1u);     // the later one at 15 is listed all the same

  EXPECT_EQ(chain[2].pair, 2);
  EXPECT_EQ(chain[2].level, static_cast<int>(Difficulty::kChallenging));
  EXPECT_EQ(chain[2].cause, SolveCause::kTransfer);
  EXPECT_EQ(chain[2].solved_by, 3);
  EXPECT_TRUE(chain[2].solved_through_transfer);
  ASSERT_EQ(chain[2].transfers_in.size(), 2u);
  EXPECT_DOUBLE_EQ(chain[2].transfers_in[1].score - chain[2].transfers_in[1].previous_score, 70.0);
}

// A transfer in the iteration of a solve by the pair's own ES step came after it, and did not bring that agent.
TEST(GoalSwitching, ATransferAfterTheSolveInTheSameIterationDidNotSolveIt) {
  RunSnapshot run = sample_run();
  run.state.pairs[1].first_solved_iteration = 15;
  run.events.erase(run.events.begin() + 2);                                       // pair 1's solve at admission
  run.events.insert(run.events.begin() + 4, event(15, "solved", {{"pair", 1}}));  // before the transfers of 15
  const RunMetrics metrics = compute_run_metrics(run);
  const std::vector<LineageLink> chain = lineage_chain(run, metrics, 1);
  ASSERT_EQ(chain.size(), 2u);
  EXPECT_EQ(chain[1].cause, SolveCause::kOwnEs);
  EXPECT_FALSE(chain[1].solved_through_transfer);
}

// A log that records what each solve followed ("by", written by the engine) is read for it, not for its order; a
// "by" the reader does not know leaves the order to say.
TEST(GoalSwitching, WhatTheEngineRecordedAsTheSolvesCauseIsReadWhereTheLogHasIt) {
  RunSnapshot run = sample_run();
  run.events[2]["by"] = "admission";
  run.events.back()["by"] = "es";  // right after a transfer into it, but the engine says its ES step solved it
  const RunMetrics metrics = compute_run_metrics(run);
  std::vector<LineageLink> chain = lineage_chain(run, metrics, 2);
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[1].cause, SolveCause::kAdmission);
  EXPECT_EQ(chain[2].cause, SolveCause::kOwnEs);
  EXPECT_EQ(chain[2].solved_by, kNone);

  run.events.back()["by"] = "a guess";
  chain = lineage_chain(run, metrics, 2);
  EXPECT_EQ(chain[2].cause, SolveCause::kTransfer);
}

TEST(GoalSwitching, UnknownPairsAndParentCyclesEndTheChain) {
  RunSnapshot run = sample_run();
  const RunMetrics metrics = compute_run_metrics(run);
  EXPECT_TRUE(lineage_chain(run, metrics, 42).empty());
  run.state.pairs[0].parent_id = 2;  // a damaged state: 0 → 2 → 1 → 0
  EXPECT_LE(lineage_chain(run, metrics, 2).size(), run.state.pairs.size() + 1);
}

}  // namespace
}  // namespace poet
