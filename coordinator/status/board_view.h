#pragma once
// What the status board holds, as a reader takes it at one moment: the run's and the dispatcher's last published
// copies and the board's own figures. The renderers (status_messages, prometheus_text) turn a view into what the
// status socket serves, without the board's lock.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"
#include "engine/annecs.h"
#include "engine/run_state.h"
#include "run_directory/files/wall_times.h"
#include "simulation/envgen/env_distance.h"

namespace poet {

// What the coordinator is doing, for /status's "state".
enum class RunPhase { kStarting, kRunning, kWaitingForWorkers, kStopping, kFinished };

// A pair without its θ and optimizer, and the environment's difficulty, computed once.
struct PairInfo {
  Pair pair;  // theta, best_theta and optimizer left empty
  int difficulty_level = 0;
};

// The run as the run loop last published it (not the run directory's RunSnapshot: no θ, no logs).
struct PublishedRun {
  RunMode mode = RunMode::kPoet;
  uint64_t seed = 0;
  int next_iteration = 0;
  int iterations = 0;
  bool finished = false;
  RunCounters counters;
  Annecs annecs;  // both definitions, as of the last iteration done
  int last_checkpoint_iteration = 0;
  std::vector<PairInfo> pairs;
  // the obstacle frontier (spec §1.4's measures) over the environments solved so far, and over those admitted
  ObstacleMeasures frontier_solved{};
  ObstacleMeasures frontier_admitted{};
  int highest_level_solved = -1;  // a Difficulty; -1 before any solve
};

struct BoardView {
  std::shared_ptr<const PublishedRun> run;       // null before the first publish_run
  std::shared_ptr<const DispatchView> dispatch;  // null without a dispatcher
  double dispatch_age_s = 0;                     // since the dispatcher's snapshot was published
  RunPhase phase = RunPhase::kStarting;
  std::string note;
  double rollouts_per_s = 0;
  double env_steps_per_s = 0;
  int64_t skipped_key_files = 0;
  int64_t cached_episodes = 0;   // answered by the score cache without running them (this process)
  int64_t cached_env_steps = 0;  // their environment steps
  PhaseSeconds phase_seconds{};  // this process's seconds in each phase of an iteration, as of the last save
  double waiting_seconds = 0;    // those of them spent waiting for rollouts
  double uptime_s = 0;           // since the board was made
};

}  // namespace poet
