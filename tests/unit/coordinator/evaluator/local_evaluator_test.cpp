// LocalEvaluator: results in task order, equal to running each task alone, whatever the thread count, each
// reported final once as its episode ends; a stop request abandons a batch, cutting its episodes short; and
// run_task's perturbed episode is the plain rollout of θ + sign·σ·ε.

#include "coordinator/evaluator/local_evaluator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "simulation/envgen/named_courses.h"
#include "simulation/es/perturbation.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

std::vector<RolloutTask> tasks() {
  RandomStream init(stream_key(8, "init"));
  auto theta = std::make_shared<const std::vector<double>>(random_params(init, 0.1));
  std::vector<RolloutTask> out;
  for (int i = 0; i < 7; ++i) {
    RolloutTask t;
    t.theta = theta;
    t.env = EnvDef{*named_course(i % 2 ? "r1" : "hard"), static_cast<uint32_t>(i)};
    t.max_steps = 150;
    if (i > 0) t.perturbation = Perturbation{stream_key(8, "noise", {uint64_t(i)}), i % 2 ? 1 : -1, 0.1};
    out.push_back(t);
  }
  return out;
}

TEST(LocalEvaluator, ResultsComeInTaskOrderWhateverTheThreadCount) {
  const std::vector<RolloutTask> batch = tasks();
  const std::vector<RolloutResult> one = LocalEvaluator(1).evaluate(batch);
  const std::vector<RolloutResult> two = LocalEvaluator(2).evaluate(batch);
  ASSERT_EQ(one.size(), batch.size());
  ASSERT_EQ(two.size(), batch.size());
  for (size_t i = 0; i < batch.size(); ++i) {
    const RolloutResult alone = run_task(batch[i]);
    EXPECT_EQ(one[i].total_reward, alone.total_reward) << i;
    EXPECT_EQ(two[i].total_reward, alone.total_reward) << i;
    EXPECT_EQ(two[i].steps, alone.steps) << i;
  }
  EXPECT_NE(one[1].total_reward, one[2].total_reward);
}

TEST(LocalEvaluator, ReportsEveryResultOnceAndNeverTwoReportsAtOnce) {
  const std::vector<RolloutTask> batch = tasks();
  std::vector<int> reported(batch.size(), 0);
  std::vector<double> returns(batch.size(), 0);
  std::atomic<bool> inside{false};
  bool overlapped = false;
  const std::vector<RolloutResult> out =
      LocalEvaluator(2).evaluate(batch, [&](size_t first, std::span<const RolloutResult> results) {
        if (inside.exchange(true)) overlapped = true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));  // gives a concurrent call its chance
        for (size_t k = 0; k < results.size(); ++k) {
          ASSERT_LT(first + k, batch.size());
          reported[first + k] += 1;
          returns[first + k] = results[k].total_reward;
        }
        inside = false;
      });
  EXPECT_FALSE(overlapped);
  ASSERT_EQ(out.size(), batch.size());
  for (size_t i = 0; i < batch.size(); ++i) {
    EXPECT_EQ(reported[i], 1) << i;
    EXPECT_EQ(returns[i], out[i].total_reward) << i;
  }
}

TEST(LocalEvaluator, AStopRequestAbandonsTheBatch) {
  std::stop_source stop;
  stop.request_stop();
  EXPECT_THROW(LocalEvaluator(2, stop.get_token()).evaluate(tasks()), EvaluationStopped);

  // requested while episodes run: a batch of 200 episodes (well over the 50 ms the stop waits on two threads) is
  // abandoned rather than finished
  std::vector<RolloutTask> many;
  for (int i = 0; i < 200; ++i) {
    RolloutTask t = tasks()[0];
    t.env = EnvDef{*named_course("flat"), static_cast<uint32_t>(i)};
    t.max_steps = 2000;
    many.push_back(t);
  }
  std::stop_source later;
  std::jthread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    later.request_stop();
  });
  EXPECT_THROW(LocalEvaluator(2, later.get_token()).evaluate(many), EvaluationStopped);
}

TEST(Rollout, AStopRequestCutsTheEpisodeShort) {
  const RolloutTask task = tasks()[0];
  std::stop_source stop;
  stop.request_stop();
  const RolloutResult r = run_task(task, stop.get_token());
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.steps, 0);
  EXPECT_FALSE(run_task(task).stopped);
}

TEST(RunTask, APerturbedTaskIsTheRolloutOfThePerturbedParameters) {
  const RolloutTask task = tasks()[3];
  std::vector<double> params(task.theta->size());
  perturb(*task.theta, task.perturbation->key, task.perturbation->sign, task.perturbation->sigma, params);
  const RolloutResult direct = rollout(params, task.env, task.walker, {task.max_steps});
  EXPECT_EQ(run_task(task).total_reward, direct.total_reward);
}

TEST(RunTask, RefusesTasksThatCannotRun) {
  RolloutTask no_theta = tasks()[0];
  no_theta.theta.reset();
  EXPECT_THROW(run_task(no_theta), std::invalid_argument);
  RolloutTask bad_sign = tasks()[1];
  bad_sign.perturbation->sign = 0;
  EXPECT_THROW(run_task(bad_sign), std::invalid_argument);
  RolloutTask short_theta = tasks()[0];
  short_theta.theta = std::make_shared<const std::vector<double>>(3, 0.0);
  EXPECT_THROW(run_task(short_theta), std::invalid_argument);
  RolloutTask bad_env = tasks()[0];
  bad_env.env.seed = kMaxEnvSeed;
  EXPECT_THROW(run_task(bad_env), std::invalid_argument);
}

}  // namespace
}  // namespace poet
