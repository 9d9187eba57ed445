// The direct-path budget from a run's lineage records, on a hand-made history.

#include "engine/lineage.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace poet {
namespace {

Pair pair_at(int id, int created, int parent, int source) {
  Pair p;
  p.id = id;
  p.created_iteration = created;
  p.parent_id = parent;
  p.initial_source_pair = source;
  return p;
}

// Pair 0 from iteration 0; pair 1 its child at 10, solved at 40 after a transfer from pair 2 at 30; pair 2 a
// child of 0 at 20; pair 3 unrelated. The run is at iteration 50.
RunState history() {
  RunState s;
  s.next_iteration = 50;
  s.pairs = {pair_at(0, 0, kNone, kNone), pair_at(1, 10, 0, 0), pair_at(2, 20, 0, 0), pair_at(3, 25, 0, 0)};
  s.pairs[1].transfers.push_back({30, 2, true, 120});
  s.pairs[1].transfers.push_back({45, 3, false, 260});  // after the solve: does not count
  s.pairs[1].first_solved_iteration = 40;
  return s;
}

TEST(Lineage, HorizonsFollowParentsSourcesAndTransfersUpToTheSolve) {
  const std::map<int, int> h = lineage_horizons(history(), 1);
  EXPECT_EQ(h, (std::map<int, int>{{0, 19}, {1, 40}, {2, 30}}));
  EXPECT_TRUE(lineage_horizons(history(), 99).empty());
}

TEST(Lineage, BudgetCountsEachContributorsStepsOnce) {
  // pair 1: iterations 10..40 (31 steps); pair 0: 0..19 (20); pair 2: 20..30 (11)
  EXPECT_EQ(lineage_es_steps(history(), 1), 31 + 20 + 11);
  // the first pair alone, unsolved: every iteration so far
  EXPECT_EQ(lineage_es_steps(history(), 0), 50);
}

TEST(Lineage, EnvironmentStepsAreEachContributorsAtItsHorizon) {
  // a pair's steps after iteration t: 1000 per ES step since its creation, plus its id (to tell them apart)
  const RunState s = history();
  std::vector<std::pair<int, int>> asked;
  const PairEnvStepsAt recorded = [&](int pair, int iteration) -> std::optional<int64_t> {
    asked.emplace_back(pair, iteration);
    return 1000 * (iteration - s.find(pair)->created_iteration + 1) + pair;
  };
  EXPECT_EQ(lineage_env_steps(s, 1, recorded), (31'000 + 1) + (20'000 + 0) + (11'000 + 2));
  EXPECT_EQ(asked, (std::vector<std::pair<int, int>>{{0, 19}, {1, 40}, {2, 30}}));
  // one contributor without the record: not known
  const PairEnvStepsAt missing = [&](int pair, int iteration) -> std::optional<int64_t> {
    if (pair == 2) return std::nullopt;
    return recorded(pair, iteration);
  };
  EXPECT_FALSE(lineage_env_steps(s, 1, missing).has_value());
  // a contributor retired before its horizon: its last step
  RunState r = history();
  r.pairs[0].retired_iteration = 15;
  asked.clear();
  EXPECT_EQ(lineage_env_steps(r, 1, recorded), (31'000 + 1) + (15'000 + 0) + (11'000 + 2));
  EXPECT_EQ(asked.front(), (std::pair<int, int>{0, 14}));
}

TEST(Lineage, RetiredContributorsStopAtTheirRetirement) {
  RunState s = history();
  s.pairs[0].retired_iteration = 15;  // its last ES step was at 14
  EXPECT_EQ(lineage_es_steps(s, 1), 31 + 15 + 11);
}

}  // namespace
}  // namespace poet
