#pragma once
// What the status board holds, as a reader takes it at one moment: the run's and the dispatcher's last published
// copies and the board's own figures. The renderers (status_messages, prometheus_text) turn a view into what the
// status socket serves, without the board's lock.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/annecs.h"
#include "engine/run_state.h"
#include "run_directory/files/wall_times.h"

namespace poet {

// One worker as the dispatcher sees it.
struct WorkerSnapshot {
  std::string id;       // any bytes: shown as is when printable ASCII, else as hex
  std::string address;  // where it connects from, or the name it gave
  int threads = 0;
  int64_t jobs_done = 0;
  int64_t results_done = 0;
  double seconds_since_heartbeat = 0;  // when published; readers add the time since
  uint64_t fingerprint_digest = 0;
};

// The dispatcher's state, as a copy.
struct DispatchSnapshot {
  std::vector<WorkerSnapshot> workers;
  int64_t queue_depth = 0;
  int64_t in_flight_jobs = 0;
  std::map<std::string, int64_t> dropped_frames;  // by reason (drop_reason.h)
  int64_t workers_joined = 0;                     // Welcomes given since the coordinator started
  int64_t workers_lost = 0;                       // workers removed for silence or a failed send
  int64_t backup_jobs = 0;                        // jobs also sent to a second worker (dispatcher.h)
  int64_t leases_expired = 0;                     // jobs taken back from workers not yet proven
  int64_t workers_demoted = 0;                    // workers not proven given no more jobs
  int64_t verified_jobs = 0;                      // answers found right by a second worker or the coordinator
  int64_t wrong_workers = 0;                      // workers refused for wrong results
  int64_t coordinator_checks = 0;                 // jobs the coordinator ran itself, no worker able to check them
  int64_t rollbacks = 0;                          // times the run went back to a checkpoint before a liar's answers
};

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
};

struct BoardView {
  std::shared_ptr<const PublishedRun> run;           // null before the first publish_run
  std::shared_ptr<const DispatchSnapshot> dispatch;  // null without a dispatcher
  double dispatch_age_s = 0;                         // since the dispatcher's snapshot was published
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
