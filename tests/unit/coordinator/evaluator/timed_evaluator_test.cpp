// TimedEvaluator: the seconds spent in evaluate() on the given clock, summed until take(), a stop's included; the
// results, the ready calls and the withdrawals are the inner evaluator's.

#include "coordinator/evaluator/timed_evaluator.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

// Answers each task with its index as the reward after advancing the fake clock by `cost`; stops when told to.
class SlowEvaluator final : public Evaluator {
 public:
  SlowEvaluator(double& clock, double cost) : clock_(clock), cost_(cost) {}
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    clock_ += cost_;
    if (stop) throw EvaluationStopped();
    std::vector<RolloutResult> out(tasks.size());
    for (size_t i = 0; i < out.size(); ++i) out[i].total_reward = static_cast<double>(i);
    if (ready) ready(0, out);
    return out;
  }
  Withdrawals withdrawals() override { return {true, 4, 2, {2}}; }
  void went_back(uint64_t last_batch) override { went_back_to = last_batch; }
  bool stop = false;
  uint64_t went_back_to = 0;

 private:
  double& clock_;
  double cost_;
};

TEST(TimedEvaluator, CountsTheSecondsInEvaluateUntilTaken) {
  double clock = 100;
  SlowEvaluator inner(clock, 2.5);
  TimedEvaluator timed(inner, [&] { return clock; });
  const std::vector<RolloutTask> tasks(3);
  size_t reported = 0;
  const std::vector<RolloutResult> results =
      timed.evaluate(tasks, [&](size_t, std::span<const RolloutResult> r) { reported += r.size(); });
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[2].total_reward, 2.0);
  EXPECT_EQ(reported, 3u);
  clock += 7;  // the loop's own work: not counted
  timed.evaluate(tasks);
  EXPECT_DOUBLE_EQ(timed.take(), 5.0);
  EXPECT_DOUBLE_EQ(timed.take(), 0.0);

  inner.stop = true;  // a stopped batch was waited for all the same
  EXPECT_THROW(timed.evaluate(tasks), EvaluationStopped);
  EXPECT_DOUBLE_EQ(timed.take(), 2.5);
}

TEST(TimedEvaluator, WithdrawalsAndGoingBackPassThrough) {
  double clock = 0;
  SlowEvaluator inner(clock, 1);
  TimedEvaluator timed(inner, [&] { return clock; });
  const Withdrawals told = timed.withdrawals();
  EXPECT_TRUE(told.possible);
  EXPECT_EQ(told.last_batch, 4u);
  EXPECT_EQ(told.withdrawn_from, std::optional<uint64_t>(2));
  timed.went_back(1);
  EXPECT_EQ(inner.went_back_to, 1u);
  EXPECT_DOUBLE_EQ(timed.take(), 0.0) << "no time in evaluate()";
}

}  // namespace
}  // namespace poet
