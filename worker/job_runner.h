#pragma once
// The thread that runs a worker's jobs. Jobs are queued in arrival order and run one at a time, each job's
// tasks spread over the worker's threads with parallel_for (results in task order, whatever the thread count).
// The socket thread never waits on it: it submits jobs, is told through a callback when an outcome is ready,
// and collects it with take_finished(). abandon() stops the job in hand and drops the rest, for a lost
// coordinator or a stop; an abandoned job is never reported.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <stop_token>
#include <thread>
#include <vector>

#include "worker/job_executor.h"

namespace poet::worker {

// Runs one job on the calling thread with up to `threads` episodes at once. A stop request on `stop` cuts it
// short; the outcome is then meaningless (the caller discards it).
JobOutcome run_job(const WorkerJob& job, int threads, std::stop_token stop = {});

// The worker's JobExecutor. Thread-safe: every member may be called from any thread (the worker calls them from
// its socket thread).
class JobRunner final : public JobExecutor {
 public:
  // threads ≥ 1: episodes run at once. on_finished is called on the runner's thread each time an outcome is
  // ready to take; it must not block (the worker writes a byte to its wake-up pipe).
  JobRunner(int threads, std::function<void()> on_finished);
  ~JobRunner() override;  // abandons the work and joins the thread
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  // Queues a job behind those already queued.
  void submit(WorkerJob job) override;

  // The outcomes finished since the last call, in the order they finished (which is arrival order).
  std::vector<JobOutcome> take_finished() override;

  // Stops the running job (its episodes end within 64 steps), drops the queued jobs and the outcomes not yet
  // taken. Returns at once; the runner takes new jobs afterwards.
  void abandon() override;

  // Jobs queued or running (for logs and tests).
  size_t pending() const;

 private:
  void loop(std::stop_token stop);

  const int threads_;
  const std::function<void()> on_finished_;
  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::deque<WorkerJob> queue_;
  std::vector<JobOutcome> finished_;
  std::stop_source running_stop_;  // the running job's stop; a fresh source per job
  bool running_ = false;
  std::jthread thread_;  // last: it starts once the members above exist
};

}  // namespace poet::worker
