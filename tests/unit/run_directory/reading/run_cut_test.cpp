// Tests run_directory/reading/run_cut.cpp: a run cut at an earlier iteration reports what the same run stopped there
// reports (runs are deterministic, so the shorter run is the longer one's past), and the budget in environment
// steps names the last iteration within it.

#include "run_directory/reading/run_cut.h"

#include <gtest/gtest.h>

#include "../../engine/engine_test_support.h"
#include "run_directory/reading/coverage.h"
#include "run_directory/reading/report_json.h"
#include "run_directory/reading/run_metrics.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

// poet-report's JSON of a run, without what names the directory or its machine.
nlohmann::ordered_json report_of(const RunSnapshot& run) {
  const RunMetrics metrics = compute_run_metrics(run);
  nlohmann::ordered_json j = report_json(run, metrics, compute_coverage(run.state, 1, 40), "");
  j.erase("run_dir");
  j.erase("iteration_limit");
  j.erase("finished");
  for (auto& level : j["levels"])
    for (const char* first : {"first_created", "first_admitted", "first_solved"})
      if (level[first].is_object()) level[first].erase("wall_s");
  return j;
}

TEST(RunCut, ACutRunReportsWhatTheRunStoppedThereReports) {
  testing::ScratchDir scratch("poet_run_cut_test");
  pb::RunConfig config = testing::small_real_run();
  config.set_iterations(7);
  ASSERT_FALSE(testing::run_in_directory(scratch.path() / "long", config, 7));
  ASSERT_FALSE(testing::run_in_directory(scratch.path() / "short", config, 4));
  Expected<RunSnapshot> long_run = read_run_snapshot(scratch.path() / "long");
  Expected<RunSnapshot> short_run = read_run_snapshot(scratch.path() / "short");
  ASSERT_TRUE(long_run && short_run);
  ASSERT_GT(long_run->state.pairs.size(), short_run->state.pairs.size()) << "the runs must differ after the cut";
  const RunSnapshot cut = cut_run(*long_run, 3);
  EXPECT_EQ(report_of(cut).dump(1), report_of(*short_run).dump(1));
  EXPECT_EQ(cut.stats.size(), short_run->stats.size());
  EXPECT_EQ(cut.events.size(), short_run->events.size());
  // cut at or past its end: unchanged
  EXPECT_EQ(report_of(cut_run(*long_run, 6)).dump(), report_of(*long_run).dump());

  // the budget: the short run's environment steps name its last iteration
  const int64_t steps = short_run->stats.back().run_env_steps;
  EXPECT_EQ(last_iteration_within(*long_run, steps), 3);
  EXPECT_EQ(last_iteration_within(*long_run, steps - 1), 2);
  EXPECT_EQ(last_iteration_within(*long_run, 0), std::nullopt);
}

}  // namespace
}  // namespace poet
