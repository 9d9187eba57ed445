#include "tests/support/test_worker/faulty_jobs.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <memory>
#include <utility>
#include <vector>

namespace poet::test_worker {
namespace {

using worker::JobOutcome;
using worker::WorkerJob;

// An executor that answers every job at once with one result of reward 10, and records what it was given.
struct InstantJobs final : worker::JobExecutor {
  std::vector<uint64_t> submitted;
  std::vector<JobOutcome> ready;
  int abandoned = 0;
  void submit(WorkerJob job) override {
    submitted.push_back(job.job_id);
    RolloutResult result;
    result.total_reward = 10;
    ready.push_back({.job_id = job.job_id, .results = {result}, .error = {}});
  }
  std::vector<JobOutcome> take_finished() override { return std::exchange(ready, {}); }
  void abandon() override {
    ++abandoned;
    ready.clear();
  }
};

struct Faulty {
  explicit Faulty(Fault fault, LieShape lie = {}) {
    auto owned = std::make_unique<InstantJobs>();
    inner = owned.get();
    jobs = std::make_unique<FaultyJobs>(fault, lie, std::move(owned), [this] { ++notified; });
  }
  InstantJobs* inner = nullptr;
  std::unique_ptr<FaultyJobs> jobs;
  int notified = 0;
};

WorkerJob job(uint64_t id, uint64_t batch = 1) { return {.job_id = id, .batch_id = batch, .tasks = {}}; }

TEST(FaultyJobs, NoFaultPassesJobsAndOutcomesThrough) {
  Faulty f(Fault::kNone);
  f.jobs->submit(job(1));
  const std::vector<JobOutcome> out = f.jobs->take_finished();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].results[0].total_reward, 10);
  f.jobs->abandon();
  EXPECT_EQ(f.inner->abandoned, 1);
}

TEST(FaultyJobs, IgnoreJobsNeverRunsNorAnswersOne) {
  Faulty f(Fault::kIgnoreJobs);
  f.jobs->submit(job(1));
  f.jobs->submit(job(2));
  EXPECT_TRUE(f.inner->submitted.empty());
  EXPECT_TRUE(f.jobs->take_finished().empty());
}

TEST(FaultyJobs, ErrorOnJobAnswersEveryJobWithAnErrorAtOnce) {
  Faulty f(Fault::kErrorOnJob);
  f.jobs->submit(job(4));
  EXPECT_TRUE(f.inner->submitted.empty());
  EXPECT_EQ(f.notified, 1) << "the loop is woken for the outcome";
  const std::vector<JobOutcome> out = f.jobs->take_finished();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].job_id, 4u);
  EXPECT_TRUE(out[0].results.empty());
  EXPECT_EQ(out[0].error, "refused on purpose (--fault error-on-job)");
  f.jobs->submit(job(5));
  f.jobs->abandon();
  EXPECT_TRUE(f.jobs->take_finished().empty()) << "an abandoned answer is never reported";
}

TEST(FaultyJobs, WrongResultsAreOffByOneWhereTheShapeSays) {
  Faulty f(Fault::kWrongResults, LieShape{.honest_jobs = 2});
  std::vector<double> rewards;
  for (uint64_t id = 1; id <= 4; ++id) {
    f.jobs->submit(job(id));
    for (const JobOutcome& o : f.jobs->take_finished()) rewards.push_back(o.results[0].total_reward);
  }
  EXPECT_EQ(rewards, (std::vector<double>{10, 10, 11, 11}));
  EXPECT_EQ(f.inner->submitted.size(), 4u);
}

// In the death test's child: no core file for the deliberate abort, then a job.
void submit_without_core(FaultyJobs& jobs) {
  const rlimit none{0, 0};
  ::setrlimit(RLIMIT_CORE, &none);
  jobs.submit(job(1));
}

TEST(FaultyJobs, CrashOnJobAbortsOnTheFirstJob) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  Faulty f(Fault::kCrashOnJob);
  EXPECT_EXIT(submit_without_core(*f.jobs), ::testing::KilledBySignal(SIGABRT), "");
}

}  // namespace
}  // namespace poet::test_worker
