#pragma once
// The paper's metrics of a run (spec §3, "Metrics the paper reports"), computed from a RunSnapshot: environments
// created, passed the minimal criterion, admitted and solved per difficulty level over iterations; iterations
// from creation to solution per level; transfer attempts and accepted transfers; ANNECS in both of its peers'
// definitions; the closest-to-target solved environment. Coverage is in coverage.h.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/annecs.h"
#include "run_directory/reading/run_snapshot.h"
#include "simulation/envgen/env_distance.h"

namespace poet {

inline constexpr int kLevels = 4;  // Difficulty: easy, challenging, very, extremely challenging

struct LevelCounts {
  std::array<int64_t, kLevels> created{};    // new environments made by mutation (duplicates of the archive excluded)
  std::array<int64_t, kLevels> passed_mc{};  // of those, the ones whose parent's θ scored within the MC bounds
  std::array<int64_t, kLevels> admitted{};   // environments that became pairs
  std::array<int64_t, kLevels> solved{};     // pairs solved (finished and ≥ solved_score), by first solve
  friend bool operator==(const LevelCounts&, const LevelCounts&) = default;
};

// The counts accumulated up to and including an iteration.
struct LevelTimePoint {
  int iteration = 0;
  LevelCounts total;
};

struct SolveTime {
  int pair = 0;
  int level = 0;
  int created = 0;
  int solved = 0;  // first-solved iteration
};

struct LevelSolveSummary {
  int count = 0;
  double mean = 0, sd = 0;  // sample standard deviation (0 for fewer than two)
  int min = 0, max = 0;
};

// The first time a level was reached, and what the run had spent by then: its counters as of that iteration's
// ES steps (pair_stats.csv; -1 when the run's log predates those columns) and its wall time when that iteration
// was saved, or the first saved iteration after it (wall_times.csv; absent when the run has none).
struct Milestone {
  int iteration = 0;
  int64_t rollouts = -1;
  int64_t env_steps = -1;
  std::optional<double> wall_s;
};

// Per level: the first environment created by mutation (not a duplicate), the first admitted, the first solved.
struct LevelFirsts {
  std::optional<Milestone> created, admitted, solved;
};

struct AcceptedTransfer {
  int iteration = 0;
  int target = 0;
  int source = 0;
  bool proposal = false;
  double score = 0;
  double previous_score = 0;  // the target's latest score before the round
};

struct TargetDistance {
  std::string target_name;
  EnvVector target{};
  std::optional<double> distance;  // normalised (§1.4); nullopt when nothing was solved
  std::string closest_env;         // the solved environment nearest the target
  EnvVector closest{};             // its 5-vector
};

// The obstacle frontier at the end of an iteration: for each of Table 1's measures (spec §1.4) — roughness, the top
// of the gap range, the top of the stump range — the largest value among the environments solved by then, and
// among those admitted by then. Obstacle courses only (a CPPN course's 5-vector is all zeros).
struct FrontierPoint {
  int iteration = 0;
  ObstacleMeasures solved{};    // roughness, gap hi, stump hi
  ObstacleMeasures admitted{};  // the same
};

// Where the run's time went in a block of iterations (wall_times.csv): the wall time of its saved iterations and
// the seconds of each phase of an iteration (poet/phase_observer.h) within it; the rest ("other") is the time
// between iterations — saving, logging. Lines of builds that did not time the phases count in the wall time only.
// waiting_s: the seconds the run loop waited for rollouts, over the lines that timed it (waited); the rest of those
// lines' wall time is the coordinator's own serial work.
struct PhaseBlock {
  int first = 0, last = 0;  // iterations, both included
  double wall_s = 0;
  PhaseSeconds phases{};
  int lines = 0, timed = 0;  // saved iterations in the block, and those with phase times
  double waiting_s = 0;
  int waited = 0;            // lines with waiting_s
  double waited_wall_s = 0;  // their wall time
};

struct RunMetrics {
  int iterations_done = 0;  // the checkpoint's next iteration
  LevelCounts total;
  int64_t duplicates = 0;                 // mutation attempts equal to an archived environment
  std::vector<LevelTimePoint> over_time;  // one point per iteration 0 .. iterations_done - 1
  std::vector<SolveTime> solve_times;
  std::array<LevelSolveSummary, kLevels> solve_summary{};
  std::array<LevelFirsts, kLevels> firsts{};
  int64_t transfer_attempts = 0, transfer_successes = 0;
  std::vector<AcceptedTransfer> accepted_transfers;
  Annecs annecs;                         // at the end of the run (poet/annecs.h)
  std::vector<Annecs> annecs_over_time;  // one per iteration 0 .. iterations_done − 1, as annecs.csv holds them
  std::optional<TargetDistance> closest_to_target;
  std::vector<FrontierPoint> frontier_over_time;  // one per iteration 0 .. iterations_done − 1
  std::vector<PhaseBlock> phase_blocks;           // about ten blocks of a round number of iterations; none without
                                                  // wall times
};

// wall_times.csv's lines in blocks of block_iterations iterations (block 0: iterations 0 .. block_iterations − 1);
// a line's wall time is its time since the line before. Blocks without a line are left out.
std::vector<PhaseBlock> phase_blocks(const std::vector<WallTime>& times, int block_iterations);
// A round number of iterations (1, 2 or 5 × 10^k) that cuts `iterations` into at most ten blocks.
int phase_block_iterations(int iterations);

// The metrics of a run. target: the environment to measure closest-to-target against; without one, a control
// run's own target (ES alone, direct path), and none for POET.
RunMetrics compute_run_metrics(const RunSnapshot& run, const std::optional<EnvEncoding>& target = std::nullopt);

}  // namespace poet
