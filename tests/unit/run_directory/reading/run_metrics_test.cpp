#include "run_directory/reading/run_metrics.h"

#include <gtest/gtest.h>

#include "common/formats/envgen/env_proto.h"

namespace poet {
namespace {

EnvEncoding course(const std::string& name, double roughness, double gap_hi, double stump_hi) {
  EnvEncoding e;
  e.name = name;
  e.roughness = roughness;
  if (gap_hi > 0) e.pit_gap = Interval{0, gap_hi};
  if (stump_hi > 0) {
    e.stump_height = Interval{0, stump_hi};
    e.stump_width = Interval{1, 2};
    e.stump_float = Interval{0, 1};
  }
  return e;
}

Pair pair(int id, EnvEncoding env, int created, int parent, int solved = kNone, int retired = kNone) {
  Pair p;
  p.id = id;
  p.env.encoding = std::move(env);
  p.created_iteration = created;
  p.parent_id = parent;
  p.first_solved_iteration = solved;
  p.retired_iteration = retired;
  return p;
}

nlohmann::json child(int iteration, std::array<double, 5> e, bool passed, bool duplicate = false) {
  nlohmann::json event = {{"iteration", iteration}, {"event", "child"}, {"e", e}, {"duplicate", duplicate}};
  if (!duplicate) event["passed_mc"] = passed;
  return event;
}

// A run of 10 iterations: flat solved at 3; an easy child admitted at 4, solved at 6, retired at 8; a
// challenging child (roughness 5) admitted at 5, solved at 9; a very challenging one (gap 6.4, stumps 2.6)
// admitted at 8, unsolved; one accepted transfer.
RunSnapshot sample_run() {
  RunSnapshot run;
  run.state.settings.iterations = 20;
  run.state.next_iteration = 10;
  run.state.pairs = {pair(0, course("flat", 0, 0, 0), 0, kNone, 3), pair(1, course("easy", 0.4, 0.8, 0.4), 4, 0, 6, 8),
                     pair(2, course("rough", 5.0, 0, 0), 5, 1, 9), pair(3, course("very", 0, 6.4, 2.6), 8, 2)};
  run.state.counters.transfer_attempts = 6;
  run.state.counters.transfer_successes = 1;
  run.events = {child(4, {0.4, 0, 0.8, 0, 0.4}, true),
                child(4, {0.6, 0, 0.8, 0, 0.4}, false),
                child(4, {0.4, 0, 0.8, 0, 0.4}, false, true),
                child(5, {5.0, 0, 0, 0, 0}, true),
                child(8, {0, 0, 6.4, 0, 2.6}, true),
                {{"iteration", 6},
                 {"event", "transfer"},
                 {"target", 1},
                 {"source", 0},
                 {"proposal", true},
                 {"score", 250.0},
                 {"previous_score", 210.0}}};
  return run;
}

TEST(RunMetrics, TheFrontierIsTheHardestSolvedAndAdmittedByEachIteration) {
  const RunMetrics m = compute_run_metrics(sample_run());
  ASSERT_EQ(m.frontier_over_time.size(), 10u);
  using Measures = std::array<double, 3>;  // roughness, gap top, stump top
  EXPECT_EQ(m.frontier_over_time[3].solved, (Measures{0, 0, 0}));
  EXPECT_EQ(m.frontier_over_time[4].admitted, (Measures{0.4, 0.8, 0.4}));
  EXPECT_EQ(m.frontier_over_time[5].solved, (Measures{0, 0, 0}));  // the easy child is solved at 6
  EXPECT_EQ(m.frontier_over_time[6].solved, (Measures{0.4, 0.8, 0.4}));
  EXPECT_EQ(m.frontier_over_time[7].admitted, (Measures{5.0, 0.8, 0.4}));
  // retiring changes nothing; the very challenging pair is admitted at 8, never solved; the rough one solved at 9
  EXPECT_EQ(m.frontier_over_time[8].admitted, (Measures{5.0, 6.4, 2.6}));
  EXPECT_EQ(m.frontier_over_time[8].solved, (Measures{0.4, 0.8, 0.4}));
  EXPECT_EQ(m.frontier_over_time[9].solved, (Measures{5.0, 0.8, 0.4}));
}

TEST(RunMetrics, CountsPerLevelAndOverTime) {
  const RunMetrics m = compute_run_metrics(sample_run());
  EXPECT_EQ(m.iterations_done, 10);
  EXPECT_EQ(m.total.created, (std::array<int64_t, 4>{2, 1, 1, 0}));
  EXPECT_EQ(m.total.passed_mc, (std::array<int64_t, 4>{1, 1, 1, 0}));
  EXPECT_EQ(m.total.admitted, (std::array<int64_t, 4>{2, 1, 1, 0}));
  EXPECT_EQ(m.total.solved, (std::array<int64_t, 4>{2, 1, 0, 0}));
  EXPECT_EQ(m.duplicates, 1);
  ASSERT_EQ(m.over_time.size(), 10u);
  EXPECT_EQ(m.over_time[3].total.solved[0], 1);  // flat at 3
  EXPECT_EQ(m.over_time[5].total.solved[0], 1);
  EXPECT_EQ(m.over_time[6].total.solved[0], 2);  // the easy child at 6
  EXPECT_EQ(m.over_time[4].total.admitted[0], 2);
  EXPECT_EQ(m.over_time[9].total, m.total);
}

// The first creation, admission and solve of each level, with the counters of that iteration's stats rows and
// the wall time saved with it; a level never reached has none, and a run without wall times has no times.
TEST(RunMetrics, WhenEachLevelWasFirstReached) {
  RunSnapshot run = sample_run();
  for (int t = 0; t < 10; ++t) {
    StatsRow row;
    row.iteration = t;
    row.run_rollouts = 100 * (t + 1);
    row.run_env_steps = 1000 * (t + 1);
    run.stats.push_back(row);
  }
  for (int t = 0; t < 10; ++t) run.wall_times.push_back({t, 2.5 * t, std::nullopt, std::nullopt});
  const RunMetrics m = compute_run_metrics(run);

  const LevelFirsts& easy = m.firsts[0];
  ASSERT_TRUE(easy.created && easy.admitted && easy.solved);
  EXPECT_EQ(easy.created->iteration, 4);
  EXPECT_EQ(easy.admitted->iteration, 0);  // the first environment
  EXPECT_EQ(easy.solved->iteration, 3);

  const LevelFirsts& challenging = m.firsts[1];
  ASSERT_TRUE(challenging.created && challenging.admitted && challenging.solved);
  EXPECT_EQ(challenging.created->iteration, 5);
  EXPECT_EQ(challenging.admitted->iteration, 5);
  EXPECT_EQ(challenging.solved->iteration, 9);
  EXPECT_EQ(challenging.solved->rollouts, 1000);
  EXPECT_EQ(challenging.solved->env_steps, 10000);
  ASSERT_TRUE(challenging.solved->wall_s);
  EXPECT_DOUBLE_EQ(*challenging.solved->wall_s, 22.5);

  const LevelFirsts& very = m.firsts[2];
  ASSERT_TRUE(very.created && very.admitted);
  EXPECT_EQ(very.created->iteration, 8);
  EXPECT_FALSE(very.solved);
  EXPECT_FALSE(m.firsts[3].created || m.firsts[3].admitted || m.firsts[3].solved);

  // saved every 4 iterations: a milestone takes the time of the first save at or after it
  run.wall_times = {{3, 7.5, std::nullopt, std::nullopt},
                    {7, 17.5, std::nullopt, std::nullopt},
                    {11, 27.5, std::nullopt, std::nullopt}};
  const RunMetrics sparse = compute_run_metrics(run);
  ASSERT_TRUE(sparse.firsts[1].solved && sparse.firsts[1].solved->wall_s);
  EXPECT_DOUBLE_EQ(*sparse.firsts[1].solved->wall_s, 27.5);   // solved at 9, saved at 11
  EXPECT_DOUBLE_EQ(*sparse.firsts[1].created->wall_s, 17.5);  // created at 5, saved at 7

  run.wall_times.clear();
  run.stats.clear();
  const RunMetrics without = compute_run_metrics(run);
  ASSERT_TRUE(without.firsts[1].solved);
  EXPECT_FALSE(without.firsts[1].solved->wall_s);
  EXPECT_EQ(without.firsts[1].solved->rollouts, -1);
}

// wall_times.csv's lines cut into blocks: each line's time since the one before, its phases summed; a line of a build
// that did not time the phases counts in the wall time only; about ten blocks of a round size.
TEST(RunMetrics, TimePerPhaseInBlocksOfIterations) {
  const std::vector<WallTime> times = {{0, 1.0, std::nullopt, std::nullopt},
                                       {1, 3.0, PhaseSeconds{0.5, 1.0, 0.1, 0.2}, std::nullopt},
                                       {2, 6.0, PhaseSeconds{0.0, 2.0, 0.2, 0.6}, std::nullopt},
                                       {5, 10.0, PhaseSeconds{1.0, 2.0, 0.5, 0.0}, std::nullopt}};
  const std::vector<PhaseBlock> blocks = phase_blocks(times, 2);
  ASSERT_EQ(blocks.size(), 3u);  // 0–1, 2–3, 4–5
  EXPECT_EQ(blocks[0].first, 0);
  EXPECT_EQ(blocks[0].last, 1);
  EXPECT_DOUBLE_EQ(blocks[0].wall_s, 3.0);
  EXPECT_EQ(blocks[0].lines, 2);
  EXPECT_EQ(blocks[0].timed, 1);
  EXPECT_DOUBLE_EQ(blocks[0].phases[1], 1.0);
  EXPECT_DOUBLE_EQ(blocks[1].wall_s, 3.0);
  EXPECT_DOUBLE_EQ(blocks[1].phases[3], 0.6);
  EXPECT_EQ(blocks[2].first, 4);
  EXPECT_EQ(blocks[2].last, 5);
  EXPECT_DOUBLE_EQ(blocks[2].wall_s, 4.0);
  EXPECT_TRUE(phase_blocks({}, 10).empty());

  EXPECT_EQ(phase_block_iterations(0), 1);
  EXPECT_EQ(phase_block_iterations(10), 1);
  EXPECT_EQ(phase_block_iterations(11), 2);
  EXPECT_EQ(phase_block_iterations(450), 50);
  EXPECT_EQ(phase_block_iterations(1001), 200);
}

TEST(RunMetrics, IterationsFromCreationToSolutionPerLevel) {
  const RunMetrics m = compute_run_metrics(sample_run());
  ASSERT_EQ(m.solve_times.size(), 3u);
  EXPECT_EQ(m.solve_summary[0].count, 2);
  EXPECT_DOUBLE_EQ(m.solve_summary[0].mean, 2.5);  // 3 and 2
  EXPECT_NEAR(m.solve_summary[0].sd, 0.7071067811865476, 1e-12);
  EXPECT_EQ(m.solve_summary[0].min, 2);
  EXPECT_EQ(m.solve_summary[0].max, 3);
  EXPECT_EQ(m.solve_summary[1].count, 1);
  EXPECT_DOUBLE_EQ(m.solve_summary[1].mean, 4);
  EXPECT_EQ(m.solve_summary[1].sd, 0);
  EXPECT_EQ(m.solve_summary[2].count, 0);
}

TEST(RunMetrics, TransfersAndBothAnnecsDefinitions) {
  const RunMetrics m = compute_run_metrics(sample_run());
  EXPECT_EQ(m.transfer_attempts, 6);
  EXPECT_EQ(m.transfer_successes, 1);
  ASSERT_EQ(m.accepted_transfers.size(), 1u);
  EXPECT_EQ(m.accepted_transfers[0].target, 1);
  EXPECT_DOUBLE_EQ(m.accepted_transfers[0].score - m.accepted_transfers[0].previous_score, 40);
  EXPECT_EQ(m.annecs.at_admission, 2);  // children 1 and 2 solved; the first pair is not a child
  EXPECT_EQ(m.annecs.at_archiving, 1);  // only child 1 retired, solved

  // over time: child 1 counts at admission from its solve (6), at archiving from its retirement (8); child 2 from 9
  ASSERT_EQ(m.annecs_over_time.size(), 10u);
  const std::vector<int> admission = {0, 0, 0, 0, 0, 0, 1, 1, 1, 2}, archiving = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1};
  for (size_t t = 0; t < 10; ++t) {
    EXPECT_EQ(m.annecs_over_time[t].at_admission, admission[t]) << t;
    EXPECT_EQ(m.annecs_over_time[t].at_archiving, archiving[t]) << t;
  }
  EXPECT_EQ(m.annecs_over_time.back(), m.annecs);
}

TEST(RunMetrics, ClosestToTargetAmongSolvedEnvironments) {
  const EnvEncoding target = course("target", 6.0, 0, 0);
  const RunMetrics m = compute_run_metrics(sample_run(), target);
  ASSERT_TRUE(m.closest_to_target);
  EXPECT_EQ(m.closest_to_target->closest_env, "rough");
  ASSERT_TRUE(m.closest_to_target->distance);
  EXPECT_NEAR(*m.closest_to_target->distance, (1.0 / 8) / std::sqrt(5.0), 1e-12);
  // POET without a target: none; ES alone: its own target, unsolved
  EXPECT_FALSE(compute_run_metrics(sample_run()).closest_to_target);
  RunSnapshot es_alone;
  es_alone.state.settings.mode = RunMode::kEsAlone;
  es_alone.state.settings.target = EnvDef{course("hard", 3, 0, 0), 0};
  es_alone.state.next_iteration = 2;
  es_alone.state.pairs = {pair(0, course("hard", 3, 0, 0), 0, kNone)};
  const RunMetrics alone = compute_run_metrics(es_alone);
  ASSERT_TRUE(alone.closest_to_target);
  EXPECT_EQ(alone.closest_to_target->target_name, "hard");
  EXPECT_FALSE(alone.closest_to_target->distance);

  // the direct path: its pair, solved on an early stage, has moved on to the unsolved target; the stages decide
  RunSnapshot direct;
  direct.state.settings.mode = RunMode::kDirectPath;
  direct.state.settings.target = EnvDef{course("hard", 3, 0, 0), 0};
  direct.state.next_iteration = 30;
  direct.state.pairs = {pair(0, course("hard", 3, 0, 0), 0, kNone, 4)};
  direct.state.stages = {{EnvDef{course("flat", 0, 0, 0), 0}, 0, 4},
                         {EnvDef{course("r1.5", 1.5, 0, 0), 0}, 5, 9},
                         {EnvDef{course("hard", 3, 0, 0), 0}, 10, kNone}};
  const RunMetrics path = compute_run_metrics(direct);
  ASSERT_TRUE(path.closest_to_target && path.closest_to_target->distance);
  EXPECT_EQ(path.closest_to_target->closest_env, "r1.5");
  EXPECT_GT(*path.closest_to_target->distance, 0);
}

}  // namespace
}  // namespace poet
