// Tests report/report_tables.cpp: poet-report's table built from a run's metrics — its sections in order, a lineage
// told link by link, the pairs' rows, what it says of missing wall times and coverage — and the coverage sample's CSV
// with every digit.

#include "report/report_tables.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <tuple>

namespace poet {
namespace {

// flat (0) solved by its ES at 2; pair 1 (child of 0, easy) admitted at 5 with 0's θ and solved then; pair 2 (child
// of 1, roughness 5: challenging) admitted at 10 from pair 3's θ and solved at 15 by a transfer from pair 3.
RunSnapshot sample_run() {
  RunSnapshot run;
  run.dir = "runs/sample";
  run.state.next_iteration = 20;
  run.state.settings.iterations = 100;
  run.state.settings.seed = 7;
  run.state.counters.rollouts = 1234;
  run.state.counters.env_steps = 2'500'000;
  // id, course, created, parent, first θ from, solved; scores and ES steps grow with the id
  const std::tuple<int, const char*, double, int, int, int, int> rows[] = {{0, "flat", 0, 0, kNone, kNone, 2},
                                                                           {1, "r1", 1, 5, 0, 0, 5},
                                                                           {2, "r5", 5, 10, 1, 3, 15},
                                                                           {3, "r2", 2, 8, 0, 0, kNone}};
  for (const auto& [id, name, roughness, created, parent, source, solved] : rows) {
    Pair& p = run.state.pairs.emplace_back();
    std::tie(p.id, p.env.encoding.name, p.env.encoding.roughness) = std::tuple(id, name, roughness);
    std::tie(p.created_iteration, p.parent_id, p.initial_source_pair, p.first_solved_iteration) =
        std::tuple(created, parent, source, solved);
    std::tie(p.admission_score, p.best_score, p.latest_score, p.es_steps) =
        std::tuple(100.0 + id, 200.0 + id, 150.0 + id, int64_t{10} * (id + 1));
  }
  // the log's lines as events.jsonl holds them
  for (const char* line : {
           R"({"iteration": 2, "event": "solved", "pair": 0})",
           R"({"iteration": 5, "event": "pair_created", "pair": 1})",
           R"({"iteration": 5, "event": "solved", "pair": 1})",
           R"({"iteration": 10, "event": "pair_created", "pair": 2})",
           R"({"iteration": 12, "event": "transfer", "target": 2, "source": 1, "proposal": false, "score": 150.0,)"
           R"( "previous_score": 120.0})",
           R"({"iteration": 15, "event": "transfer", "target": 2, "source": 3, "proposal": true, "score": 240.0,)"
           R"( "previous_score": 170.0})",
           R"({"iteration": 15, "event": "solved", "pair": 2})"})
    run.events.push_back(nlohmann::json::parse(line));
  return run;
}

std::string table_of(const RunSnapshot& run, const std::string& samples_file = "") {
  const RunMetrics metrics = compute_run_metrics(run);
  const Coverage coverage = compute_coverage(run.state, kDefaultCoverageSeed, 10);
  return report_table(run, metrics, coverage, samples_file);
}

// Each section's first line, in the order poet-report has always printed them.
TEST(ReportTables, TheSectionsComeInTheirOrder) {
  const std::string table = table_of(sample_run());
  EXPECT_EQ(table.rfind("Run runs/sample: POET, seed 7, 20 of 100 iterations done\n1234 rollouts, 2.5 M environment "
                        "steps\n\n",
                        0),
            0u);
  size_t at = 0;
  for (const char* heading : {"\nEnvironments by difficulty level", "\nWhen each level was first reached",
                              "\nTransfers: ", "\nLineage of each environment solved at challenging or above",
                              "\nANNECS at admission: ", "\nObstacle frontier", "\nCoverage (seed 20190101, 10 "
                              "samples per level", "\n\nPairs\n"}) {
    const size_t found = table.find(heading, at);
    ASSERT_NE(found, std::string::npos) << heading << " after offset " << at << " in\n" << table;
    at = found + 1;
  }
  EXPECT_EQ(table.back(), '\n');
}

// A lineage is told link by link: where each pair's first θ came from, the transfers it took and what solved it.
TEST(ReportTables, ALineageToldLinkByLink) {
  const std::string table = table_of(sample_run());
  EXPECT_NE(table.find("  pair 2: 3 environments, 1 of them solved by an agent that came through a transfer\n"
                       "    pair 0 flat (easy), created 0; solved at 2 by its own ES\n"
                       "    pair 1 r1 (easy), created 5, first θ from pair 0 (direct, 101.0); solved at 5 at admission "
                       "from pair 0\n"
                       "    pair 2 r5 (challenging), created 10, first θ from pair 3 (direct, 102.0); transfer at 12 "
                       "from pair 1 (direct) +30.0 (120.0 → 150.0); transfer at 15 from pair 3 (proposal) +70.0 "
                       "(170.0 → 240.0); solved at 15 by a transfer from pair 3, by an agent that came through a "
                       "transfer\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("  largest gain: +70.0 (pair 2 from pair 3, proposal, iteration 15: 170.0 → 240.0)\n"),
            std::string::npos);
}

// A row a pair, with "-" where it has no parent, no source, no solve or is still active.
TEST(ReportTables, APairsRowSaysWhatItHasNotWithADash) {
  const std::string table = table_of(sample_run());
  EXPECT_NE(table.find("\n     0 flat                         easy               0      -      -       2       -    "
                       "200.0    150.0       10     0\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("\n     3 r2                           easy               8      0      0       -       -    "
                       "203.0    153.0       40     0\n"),
            std::string::npos);
}

// What the run lacks is said, not left out: wall times, a solve at challenging for coverage; the samples file named.
TEST(ReportTables, MissingWallTimesAndUndefinedCoverageAreSaid) {
  RunSnapshot run = sample_run();
  EXPECT_NE(table_of(run).find("  (no wall times: the run directory has no wall_times.csv)\n"), std::string::npos);
  run.wall_times_problem = "wall_times.csv: line 3 is damaged";
  EXPECT_NE(table_of(run).find("  (no wall times: wall_times.csv: line 3 is damaged)\n"), std::string::npos);

  run.state.pairs[2].first_solved_iteration = kNone;
  run.events.pop_back();
  const std::string table = table_of(run, "out/coverage.csv");
  EXPECT_NE(table.find("  not defined: the run solved no environment at challenging or above\n"
                       "  samples and per-sample distances: out/coverage.csv\n"),
            std::string::npos)
      << table;
  EXPECT_EQ(table.find("Lineage of each environment solved at challenging"), std::string::npos);
}

TEST(ReportTables, TheCoverageSampleKeepsEveryDigit) {
  Coverage coverage;
  coverage.samples = {{1, {0.1, 2, 3, 0.5, 1.0 / 3}, 0.25}, {3, {8, 7.5, 8, 3, 3}, std::nullopt}};
  EXPECT_EQ(coverage_samples_csv(coverage),
            "level,roughness,gap_lo,gap_hi,stump_lo,stump_hi,distance\n"
            "challenging,0.10000000000000001,2,3,0.5,0.33333333333333331,0.25\n"
            "extremely challenging,8,7.5,8,3,3,\n");
}

// The plots draw the lineage the table shows last; a run whose table shows none draws its first pair's.
TEST(ReportTables, TheDeepestPairIsTheLastLineageShown) {
  RunSnapshot run = sample_run();
  EXPECT_EQ(deepest_pair(run), 2);
  run.state.pairs.resize(1);
  run.state.pairs[0].id = 4;
  run.events.clear();
  EXPECT_EQ(deepest_pair(run), 4);
}

}  // namespace
}  // namespace poet
