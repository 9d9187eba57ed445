#pragma once
// A run's agents on a held-out test suite (poet-eval --run-dir, poet-report --suite): every
// pair's θ, active or retired, and its best θ where it differs, each on the whole suite with the run's walker; then
// the run's best single agent on the suite and its best agent per group. Best is the most episodes finished, then
// the further mean progress along the courses, then the higher mean return, then the earlier candidate.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/run_state.h"
#include "simulation/suite/course_suite.h"

namespace poet {

struct SuiteCandidate {
  int pair = 0;
  bool best_theta = false;  // the pair's best θ rather than its current one
  std::string label;        // "pair 12" or "pair 12 best"
  std::vector<double> theta;
};

struct RunSuite {
  std::vector<SuiteCandidate> candidates;  // in the archive's order, each pair's θ before its best θ
  std::vector<SuiteScore> scores;          // scores[i] is candidates[i]'s
  size_t best = 0;                         // the best single agent (an index into both); none when empty
  std::vector<size_t> best_per_group;      // per suite group, the best candidate on that group alone
};

std::vector<SuiteCandidate> suite_candidates(const RunState& state);

// Runs every candidate on the suite (episodes on up to `threads` threads; the result does not depend on them).
RunSuite evaluate_run_on_suite(const RunState& state, const CourseSuite& suite, int threads);

// One line per candidate (finished per group and in all, mean progress and return), then the best single agent and the
// best per group; for a run without candidates, a line that says so.
std::string run_suite_table(const RunSuite& run);

// {"suite", "run_dir", "candidates": [{"label", "pair", "best_theta", "score": {...}}], "best": label,
//  "best_per_group": {group: label}}; each score is suite_score_json.h's, with every episode when `episodes`.
nlohmann::json run_suite_json(const RunSuite& run, const CourseSuite& suite, const std::string& run_dir, bool episodes);

}  // namespace poet
