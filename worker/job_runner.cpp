#include "worker/job_runner.h"

#include <exception>
#include <stdexcept>
#include <utility>

#include "simulation/parallel_for.h"

namespace poet::worker {

JobOutcome run_job(const WorkerJob& job, int threads, std::stop_token stop) {
  JobOutcome outcome;
  outcome.job_id = job.job_id;
  std::vector<RolloutResult> results(job.tasks.size());
  try {
    parallel_for(static_cast<int>(job.tasks.size()), threads, [&](int i) {
      if (stop.stop_requested()) return;
      try {
        results[i] = run_task(job.tasks[i], stop);
      } catch (const std::exception& e) {
        // name the task: parallel_for rethrows only the first error, without its index
        throw std::runtime_error("tasks[" + std::to_string(i) + "]: " + e.what());
      }
    });
    outcome.results = std::move(results);
  } catch (const std::exception& e) {
    outcome.error = e.what();
  }
  return outcome;
}

JobRunner::JobRunner(int threads, std::function<void()> on_finished)
    : threads_(std::max(1, threads)),
      on_finished_(std::move(on_finished)),
      thread_([this](std::stop_token stop) { loop(std::move(stop)); }) {}

JobRunner::~JobRunner() {
  thread_.request_stop();
  abandon();
  thread_.join();
}

void JobRunner::submit(WorkerJob job) {
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(job));
  }
  wake_.notify_one();
}

std::vector<JobOutcome> JobRunner::take_finished() {
  std::lock_guard lock(mutex_);
  return std::exchange(finished_, {});
}

void JobRunner::abandon() {
  std::lock_guard lock(mutex_);
  queue_.clear();
  finished_.clear();
  running_stop_.request_stop();  // the running job sees it, and loop() then drops its outcome
}

size_t JobRunner::pending() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + (running_ ? 1 : 0);
}

void JobRunner::loop(std::stop_token stop) {
  for (;;) {
    WorkerJob job;
    std::stop_source job_stop;
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [&] { return !queue_.empty(); })) return;
      job = std::move(queue_.front());
      queue_.pop_front();
      running_stop_ = job_stop;  // abandon() stops this job through it
      running_ = true;
    }
    JobOutcome outcome = run_job(job, threads_, job_stop.get_token());
    job = {};  // its θ references go before the next wait, so a dropped batch's θs are freed now
    {
      std::lock_guard lock(mutex_);
      running_ = false;
      if (job_stop.stop_requested()) continue;  // abandoned: its results (some cut short) mean nothing
      finished_.push_back(std::move(outcome));
    }
    if (on_finished_) on_finished_();
  }
}

}  // namespace poet::worker
