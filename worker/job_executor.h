#pragma once
// A worker's job as the session hands it on, its outcome, and what the socket loop needs of whatever runs jobs:
// decoded jobs go in as the session accepts them, outcomes come out once ready, and a lost coordinator or a stop
// abandons the lot. The loop owns no executor: its caller makes one and tells it whom to wake when an outcome is
// ready. JobRunner (job_runner.h) runs jobs on this machine's threads; a program built on the worker
// (worker_command.h) may put another executor in its place.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "simulation/rollout_task.h"

namespace poet::worker {

// A job decoded from the wire, ready to run. Its tasks hold their θ (shared pointers), so a queued job needs
// nothing from the worker's θ cache and the cache can drop a batch's θs while its jobs wait.
struct WorkerJob {
  uint64_t job_id = 0;
  uint64_t batch_id = 0;
  std::vector<RolloutTask> tasks;
};

// What became of a job: one result per task in task order, or (results empty) the error of a task that could not
// run, naming it ("tasks[3]: ...").
struct JobOutcome {
  uint64_t job_id = 0;
  std::vector<RolloutResult> results;
  std::optional<std::string> error;
};

// Called from the socket loop's thread (an implementation may allow more).
class JobExecutor {
 public:
  virtual ~JobExecutor() = default;

  // Takes a job; its outcome comes out of take_finished() later (or never, when abandoned).
  virtual void submit(WorkerJob job) = 0;

  // The outcomes ready since the last call, in the order they became ready.
  virtual std::vector<JobOutcome> take_finished() = 0;

  // Stops the job in hand and drops the rest and the outcomes not yet taken: none of them is ever reported.
  // Returns at once; jobs submitted afterwards run as usual.
  virtual void abandon() = 0;
};

}  // namespace poet::worker
