// CachingEvaluator: an unperturbed task seen before, or repeated within a batch, is not run again and gets the
// result it had; perturbed tasks always run; every index is reported ready once with its final result; the memory
// bound evicts the oldest; clear() forgets; an inner evaluator's stop or wrong count passes through, and so do its
// withdrawals, the cache forgetting everything when the run goes back.

#include "coordinator/evaluator/caching_evaluator.h"

#include <gtest/gtest.h>

#include <map>

#include "coordinator/evaluator/local_evaluator.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

// Runs tasks on one thread and remembers how many it ran.
class CountingEvaluator final : public Evaluator {
 public:
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    ran += static_cast<int>(tasks.size());
    std::vector<RolloutResult> out = threads.evaluate(tasks);
    if (ready && !out.empty()) ready(0, out);  // all at once, as one range
    return out;
  }
  LocalEvaluator threads{1};
  int ran = 0;
};

// The same, withdrawing results as a verifying remote evaluator does, and remembering where the caller went back to.
class WithdrawingEvaluator final : public Evaluator {
 public:
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    return counting.evaluate(tasks, ready);
  }
  Withdrawals withdrawals() override { return told; }
  void went_back(uint64_t last_batch) override { went_back_to = last_batch; }
  CountingEvaluator counting;
  Withdrawals told{true, 7, 5, {3, 5}};
  std::optional<uint64_t> went_back_to;
};

std::shared_ptr<const std::vector<double>> theta(uint64_t seed) {
  RandomStream init(stream_key(seed, "init"));
  return std::make_shared<const std::vector<double>>(random_params(init, 0.1));
}

RolloutTask task(std::shared_ptr<const std::vector<double>> params, const char* course, uint32_t seed) {
  RolloutTask t;
  t.theta = std::move(params);
  t.env = EnvDef{*named_course(course), seed};
  t.max_steps = 120;
  return t;
}

void expect_same(const RolloutResult& a, const RolloutResult& b) {
  EXPECT_EQ(a.total_reward, b.total_reward);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.finished, b.finished);
  EXPECT_EQ(a.fell, b.fell);
}

TEST(CachingEvaluator, AKnownOrRepeatedEpisodeIsNotRunAgainAndHasTheSameResult) {
  CountingEvaluator inner;
  CachingEvaluator cache(inner, kScoreCacheBytes);
  const auto a = theta(1);
  const auto b = theta(2);
  RolloutTask perturbed = task(a, "hard", 3);
  perturbed.perturbation = Perturbation{stream_key(1, "noise"), 1, 0.1};
  // a repeat within the batch (0 and 2), a perturbed task, and a θ equal in value but another object (4)
  const std::vector<RolloutTask> first = {task(a, "hard", 3), task(b, "hard", 3), task(a, "hard", 3), perturbed,
                                          task(std::make_shared<const std::vector<double>>(*a), "r1", 5)};
  const std::vector<RolloutResult> direct = LocalEvaluator(1).evaluate(first);
  std::map<size_t, int> reported;
  const std::vector<RolloutResult> got = cache.evaluate(first, [&](size_t i, std::span<const RolloutResult> r) {
    for (size_t j = 0; j < r.size(); ++j) {
      reported[i + j] += 1;
      expect_same(r[j], direct[i + j]);
    }
  });
  ASSERT_EQ(got.size(), first.size());
  for (size_t i = 0; i < got.size(); ++i) expect_same(got[i], direct[i]);
  EXPECT_EQ(inner.ran, 4) << "the repeat within the batch ran once";
  EXPECT_EQ(cache.episodes_saved(), 1);
  EXPECT_EQ(cache.steps_saved(), direct[2].steps);
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(reported[i], 1) << i;

  // again, and the r1 episode of θ a by a copy of θ: only the perturbed task runs
  std::vector<RolloutTask> second = first;
  second[4].theta = std::make_shared<const std::vector<double>>(*a);
  reported.clear();
  const std::vector<RolloutResult> again = cache.evaluate(second, [&](size_t i, std::span<const RolloutResult> r) {
    for (size_t j = 0; j < r.size(); ++j) reported[i + j] += 1;
  });
  for (size_t i = 0; i < again.size(); ++i) expect_same(again[i], direct[i]);
  EXPECT_EQ(inner.ran, 5);
  EXPECT_EQ(cache.episodes_saved(), 5);
  for (size_t i = 0; i < second.size(); ++i) EXPECT_EQ(reported[i], 1) << i;

  // another seed, course or step limit is another episode
  RolloutTask longer = first[0];
  longer.max_steps = 121;
  cache.evaluate(std::vector<RolloutTask>{task(a, "hard", 4), task(a, "r1", 3), longer});
  EXPECT_EQ(inner.ran, 8);

  cache.clear();
  EXPECT_EQ(cache.size(), 0u);
  cache.evaluate(std::vector<RolloutTask>{first[0]});
  EXPECT_EQ(inner.ran, 9) << "forgotten";
}

TEST(CachingEvaluator, WithdrawalsPassThroughAndGoingBackForgetsEveryResult) {
  CountingEvaluator never;
  EXPECT_FALSE(CachingEvaluator(never, kScoreCacheBytes).withdrawals().possible) << "by default nothing is withdrawn";

  WithdrawingEvaluator inner;
  CachingEvaluator cache(inner, kScoreCacheBytes);
  const std::vector<RolloutTask> batch = {task(theta(1), "flat", 0)};
  cache.evaluate(batch);
  cache.evaluate(batch);
  EXPECT_EQ(inner.counting.ran, 1);
  const Withdrawals told = cache.withdrawals();
  EXPECT_TRUE(told.possible);
  EXPECT_EQ(told.last_batch, 7u);
  EXPECT_EQ(told.withdrawn_from, std::optional<uint64_t>(5));
  EXPECT_EQ(told.reachable, (std::vector<uint64_t>{3, 5}));

  cache.went_back(4);
  EXPECT_EQ(inner.went_back_to, std::optional<uint64_t>(4));
  EXPECT_EQ(cache.size(), 0u);
  cache.evaluate(batch);
  EXPECT_EQ(inner.counting.ran, 2) << "the result remembered before going back may be a lie";
}

TEST(CachingEvaluator, TheMemoryBoundEvictsTheOldest) {
  CountingEvaluator inner;
  CachingEvaluator probe(inner, kScoreCacheBytes);
  probe.evaluate(std::vector<RolloutTask>{task(theta(1), "flat", 0)});
  const size_t one = probe.bytes();
  ASSERT_GT(one, 0u);
  CachingEvaluator cache(inner, 2 * one);  // room for two results
  std::vector<RolloutTask> three;
  for (uint32_t seed = 0; seed < 3; ++seed) three.push_back(task(theta(1), "flat", seed));
  cache.evaluate(three);
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_LE(cache.bytes(), 2 * one);
  inner.ran = 0;
  cache.evaluate(std::vector<RolloutTask>{three[2], three[1]});
  EXPECT_EQ(inner.ran, 0) << "the newest two are kept";
  cache.evaluate(std::vector<RolloutTask>{three[0]});
  EXPECT_EQ(inner.ran, 1) << "the oldest was evicted";
  CachingEvaluator none(inner, 0);
  none.evaluate(three);
  EXPECT_EQ(none.size(), 0u) << "a bound of 0 keeps nothing";
}

TEST(CachingEvaluator, AnInnerEvaluatorsStopOrWrongCountPassesThrough) {
  class Stopping final : public Evaluator {
   public:
    using Evaluator::evaluate;
    std::vector<RolloutResult> evaluate(std::span<const RolloutTask>, const ResultsReady&) override {
      throw EvaluationStopped();
    }
  } stopping;
  CachingEvaluator stopped(stopping, kScoreCacheBytes);
  EXPECT_THROW(stopped.evaluate(std::vector<RolloutTask>{task(theta(1), "flat", 0)}), EvaluationStopped);
  EXPECT_EQ(stopped.size(), 0u);

  class Short final : public Evaluator {
   public:
    using Evaluator::evaluate;
    std::vector<RolloutResult> evaluate(std::span<const RolloutTask>, const ResultsReady&) override { return {}; }
  } short_answer;
  CachingEvaluator wrong(short_answer, kScoreCacheBytes);
  EXPECT_THROW(wrong.evaluate(std::vector<RolloutTask>{task(theta(1), "flat", 0)}), std::runtime_error);
  EXPECT_TRUE(wrong.evaluate(std::vector<RolloutTask>{}).empty());
}

}  // namespace
}  // namespace poet
