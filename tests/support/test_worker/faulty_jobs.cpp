#include "tests/support/test_worker/faulty_jobs.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <utility>

namespace poet::test_worker {

FaultyJobs::FaultyJobs(Fault fault, LieShape lie, std::unique_ptr<worker::JobExecutor> inner,
                       std::function<void()> on_finished)
    : fault_(fault), liar_(lie), inner_(std::move(inner)), on_finished_(std::move(on_finished)) {}

void FaultyJobs::submit(worker::WorkerJob job) {
  switch (fault_) {
    case Fault::kCrashOnJob:
      spdlog::critical("a Job arrived and --fault crash-on-job is set: aborting");
      spdlog::default_logger()->flush();
      std::abort();
    case Fault::kIgnoreJobs:
      spdlog::debug("job {}: ignored (--fault ignore-jobs)", job.job_id);
      return;
    case Fault::kErrorOnJob:
      spdlog::debug("job {}: refused on purpose (--fault error-on-job)", job.job_id);
      refused_.push_back({.job_id = job.job_id, .results = {}, .error = "refused on purpose (--fault error-on-job)"});
      if (on_finished_) on_finished_();
      return;
    case Fault::kWrongResults:
      batch_of_job_[job.job_id] = job.batch_id;
      break;
    case Fault::kNone:
      break;
  }
  inner_->submit(std::move(job));
}

std::vector<worker::JobOutcome> FaultyJobs::take_finished() {
  std::vector<worker::JobOutcome> outcomes = std::exchange(refused_, {});
  for (worker::JobOutcome& outcome : inner_->take_finished()) {
    if (fault_ == Fault::kWrongResults) {
      const uint64_t batch = batch_of_job_[outcome.job_id];
      batch_of_job_.erase(outcome.job_id);
      if (!outcome.error && liar_.lies_on(outcome.job_id, batch)) {
        spdlog::info("--fault wrong-results: a wrong answer to job {}", outcome.job_id);
        for (RolloutResult& r : outcome.results) r.total_reward += 1;
      }
    }
    outcomes.push_back(std::move(outcome));
  }
  return outcomes;
}

void FaultyJobs::abandon() {
  inner_->abandon();
  refused_.clear();
  batch_of_job_.clear();
}

}  // namespace poet::test_worker
