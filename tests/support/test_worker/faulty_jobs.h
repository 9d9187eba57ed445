#pragma once
// The test worker's JobExecutor: the worker's own runner with a fault in front of it, for the coordinator's tests
// of a peer that misbehaves. Jobs reach it decoded and checked by the worker's session, so every fault acts on a
// job the coordinator meant; the session, the loop and the wire stay the production worker's.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "tests/support/test_worker/lie_shape.h"
#include "worker/job_executor.h"

namespace poet::test_worker {

enum class Fault {
  kNone,
  kCrashOnJob,    // abort() on receiving a Job: the coordinator's poison-job rule must stop it killing every worker
  kIgnoreJobs,    // never answer a Job, but keep heartbeating: the coordinator's lease must expire
  kErrorOnJob,    // answer every Job with an error Result: one such peer must not stop the run
  kWrongResults,  // answer with well-formed results whose returns are off by one (LieShape says which): a liar
};

// As the worker's executors, called from the socket loop's thread only.
class FaultyJobs final : public worker::JobExecutor {
 public:
  // Runs the jobs the fault lets through on `inner`; `on_finished` is called when this executor makes an outcome
  // itself (error-on-job), as `inner` calls its own.
  FaultyJobs(Fault fault, LieShape lie, std::unique_ptr<worker::JobExecutor> inner, std::function<void()> on_finished);

  void submit(worker::WorkerJob job) override;
  std::vector<worker::JobOutcome> take_finished() override;
  void abandon() override;

 private:
  const Fault fault_;
  Liar liar_;
  const std::unique_ptr<worker::JobExecutor> inner_;
  const std::function<void()> on_finished_;
  std::vector<worker::JobOutcome> refused_;    // error-on-job's answers, not yet taken
  std::map<uint64_t, uint64_t> batch_of_job_;  // wrong-results: the batch of each job in hand, for LieShape's rule
};

}  // namespace poet::test_worker
