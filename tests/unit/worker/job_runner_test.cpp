#include "worker/job_runner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <chrono>
#include <memory>
#include <thread>

#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet::worker {
namespace {

using namespace std::chrono_literals;

WorkerJob make_job(uint64_t id, int tasks, int max_steps) {
  RandomStream rng(stream_key(id, "init"));
  auto theta = std::make_shared<const std::vector<double>>(random_params(rng));
  WorkerJob job{.job_id = id, .batch_id = 1, .tasks = {}};
  for (int i = 0; i < tasks; ++i) {
    RolloutTask task;
    task.theta = theta;
    task.env = EnvDef{*named_course(i % 2 == 0 ? "flat" : "r3"), static_cast<uint32_t>(i)};
    if (i % 3 != 0)
      task.perturbation = Perturbation{.key = static_cast<uint64_t>(i), .sign = i % 2 ? 1 : -1, .sigma = 0.05};
    task.max_steps = max_steps;
    job.tasks.push_back(task);
  }
  return job;
}

// Waits (bounded) until the runner has reported `count` outcomes in all.
std::vector<JobOutcome> wait_for(JobRunner& runner, size_t count) {
  std::vector<JobOutcome> all;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (all.size() < count && std::chrono::steady_clock::now() < deadline) {
    for (JobOutcome& o : runner.take_finished()) all.push_back(std::move(o));
    std::this_thread::sleep_for(1ms);
  }
  return all;
}

TEST(JobRunner, RunsJobsInArrivalOrderWithResultsInTaskOrder) {
  std::atomic<int> notified{0};
  JobRunner runner(2, [&] { ++notified; });
  const WorkerJob a = make_job(1, 5, 60);
  const WorkerJob b = make_job(2, 3, 40);
  runner.submit(a);
  runner.submit(b);
  const std::vector<JobOutcome> outcomes = wait_for(runner, 2);
  ASSERT_EQ(outcomes.size(), 2u);
  EXPECT_EQ(notified.load(), 2);
  EXPECT_EQ(outcomes[0].job_id, 1u);
  EXPECT_EQ(outcomes[1].job_id, 2u);
  for (const auto& [job, outcome] : {std::pair{&a, &outcomes[0]}, std::pair{&b, &outcomes[1]}}) {
    EXPECT_FALSE(outcome->error);
    ASSERT_EQ(outcome->results.size(), job->tasks.size());
    for (size_t i = 0; i < job->tasks.size(); ++i) {
      const RolloutResult expected = run_task(job->tasks[i]);
      EXPECT_EQ(std::bit_cast<uint64_t>(outcome->results[i].total_reward),
                std::bit_cast<uint64_t>(expected.total_reward));
      EXPECT_EQ(outcome->results[i].steps, expected.steps);
    }
  }
  EXPECT_EQ(runner.pending(), 0u);
}

TEST(JobRunner, ATaskThatCannotRunFailsTheJobNamingIt) {
  WorkerJob job = make_job(3, 4, 20);
  job.tasks[2].perturbation = Perturbation{.key = 1, .sign = 3, .sigma = 0.1};
  const JobOutcome outcome = run_job(job, 2);
  ASSERT_TRUE(outcome.error);
  EXPECT_TRUE(outcome.error->starts_with("tasks[2]: ")) << *outcome.error;
  EXPECT_TRUE(outcome.results.empty());
}

TEST(JobRunner, AbandonStopsTheRunningJobAndDropsTheQueue) {
  JobRunner runner(2, [] {});
  runner.submit(make_job(4, 200, 2000));  // minutes of work
  runner.submit(make_job(5, 2, 10));
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(runner.pending(), 2u);
  const auto started = std::chrono::steady_clock::now();
  runner.abandon();
  while (runner.pending() > 0 && std::chrono::steady_clock::now() - started < 5s) std::this_thread::sleep_for(1ms);
  EXPECT_EQ(runner.pending(), 0u);
  EXPECT_LT(std::chrono::steady_clock::now() - started, 1s);
  EXPECT_TRUE(runner.take_finished().empty());  // neither job is reported
  // and it takes new work afterwards
  runner.submit(make_job(6, 2, 10));
  const std::vector<JobOutcome> outcomes = wait_for(runner, 1);
  ASSERT_EQ(outcomes.size(), 1u);
  EXPECT_EQ(outcomes[0].job_id, 6u);
}

}  // namespace
}  // namespace poet::worker
