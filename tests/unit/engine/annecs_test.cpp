// Tests engine/annecs.cpp: both ANNECS definitions on a hand-made archive, and the values the engine
// reports at the end of each iteration equal to those read back from the final state.

#include "engine/annecs.h"

#include <gtest/gtest.h>

#include "engine_test_support.h"
#include "scripted_evaluator.h"

namespace poet::testing {
namespace {

// The first pair solved at 1 and retired at 6; child 1 (created 2) solved at 4, retired at 6; child 2 (created 3)
// retired at 5 unsolved; child 3 (created 4) solved at 7, active.
RunState archive() {
  RunState s = state_at(tiny_config(), 9, 0);
  s.pairs[0].first_solved_iteration = 1;
  s.pairs[0].retired_iteration = 6;
  for (int id = 1; id <= 3; ++id) {
    Pair& p = add_pair(s, rough(id), 0);
    p.parent_id = 0;
    p.created_iteration = id + 1;
  }
  s.pairs[1].first_solved_iteration = 4;
  s.pairs[1].retired_iteration = 6;
  s.pairs[2].retired_iteration = 5;
  s.pairs[3].first_solved_iteration = 7;
  return s;
}

TEST(Annecs, BothDefinitionsOverTime) {
  const RunState s = archive();
  // at admission: children only, from their solve (4, 7); at archiving: solved pairs, from their retirement (6, 6)
  const std::vector<Annecs> expected = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {1, 0}, {1, 0}, {1, 2}, {2, 2}, {2, 2}};
  EXPECT_EQ(annecs_over_time(s), expected);
  for (int t = 0; t < 9; ++t) EXPECT_EQ(annecs_at(s, t), expected[static_cast<size_t>(t)]) << t;
  EXPECT_EQ(annecs_at(s, -1), (Annecs{0, 0}));
  EXPECT_EQ(annecs_at(s, 100), expected.back());  // beyond the state: its last values
  RunState fresh = state_at(tiny_config(), 0, 0);
  EXPECT_TRUE(annecs_over_time(fresh).empty());
}

// A run that admits a child at every reproduction and retires past a cap of 2, where only environments with an
// even terrain seed are finished: the engine's value at each iteration's end is the one the last state gives.
TEST(Annecs, TheEnginesValuesAreThoseOfTheFinalState) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_mutation_interval(2);
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_active_cap(2);
  RunState s = state_at(c, 0, 0);
  ScriptedEvaluator ev(
      [](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0.0 : 240.0, t.env.seed % 2 == 0); });
  std::vector<Annecs> reported;
  for (int t = 0; t < 24; ++t) reported.push_back(run_iteration(s, ev).annecs);
  EXPECT_EQ(reported, annecs_over_time(s));
  EXPECT_GT(reported.back().at_admission, 0);
  EXPECT_GT(reported.back().at_archiving, 0);
  EXPECT_LT(reported.back().at_admission, static_cast<int>(s.pairs.size()) - 1);  // not every child was solved
}

}  // namespace
}  // namespace poet::testing
