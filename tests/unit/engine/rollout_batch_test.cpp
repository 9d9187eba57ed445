// How ES steps and evaluations become tasks: mirrored pairs, keys, σ, course seeds (fixed or stochastic), and
// how results come back (gradient slices, mean scores, finished only when every episode finished).

#include "engine/rollout_batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <set>
#include <thread>

#include "engine_test_support.h"
#include "scripted_evaluator.h"
#include "simulation/es/es_gradient.h"

namespace poet::testing {
namespace {

// Reports a batch's results from another thread in pieces of 1 to 7 results, in a scrambled order, then
// returns them; or, given throw_after, reports that many pieces in task order and throws.
class PiecemealEvaluator final : public Evaluator {
 public:
  using Script = std::function<RolloutResult(size_t index)>;
  explicit PiecemealEvaluator(Script script, int throw_after = -1)
      : script_(std::move(script)), throw_after_(throw_after) {}
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    std::vector<RolloutResult> out;
    for (size_t i = 0; i < tasks.size(); ++i) out.push_back(script_(i));
    std::mt19937 rng(17);
    std::vector<std::pair<size_t, size_t>> pieces;  // [first, end)
    for (size_t first = 0; first < out.size();) {
      const size_t end = std::min(out.size(), first + 1 + rng() % 7);
      pieces.emplace_back(first, end);
      first = end;
    }
    if (throw_after_ < 0) std::shuffle(pieces.begin(), pieces.end(), rng);
    std::jthread reporter([&] {
      for (int p = 0; p < static_cast<int>(pieces.size()) && p != throw_after_; ++p) {
        const auto [first, end] = pieces[static_cast<size_t>(p)];
        ready(first, std::span(out).subspan(first, end - first));
      }
    });
    reporter.join();
    if (throw_after_ >= 0) throw std::runtime_error("worker lost");
    return out;
  }

 private:
  Script script_;
  int throw_after_;
};

// Distinct returns from a hash of the task index.
RolloutResult hashed(size_t i) { return scored(static_cast<double>(mix64(i) >> 44) / 1000.0); }

bool same_bits(const EsOutcome& a, const EsOutcome& b) {
  return a.gradient.size() == b.gradient.size() &&
         std::memcmp(a.gradient.data(), b.gradient.data(), a.gradient.size() * sizeof(double)) == 0 &&
         std::memcmp(&a.mean_return, &b.mean_return, sizeof(double)) == 0 &&
         std::memcmp(&a.max_return, &b.max_return, sizeof(double)) == 0;
}

EpisodeSettings settings(bool stochastic) {
  pb::RunConfig c = tiny_config();
  c.mutable_walker()->set_stochastic_envs(stochastic);
  c.mutable_walker()->set_eval_episodes(3);
  c.mutable_walker()->set_max_steps(123);
  return run_settings(c).episodes;
}

TEST(RolloutBatch, AnEsStepIsMirroredPairsOnTheEnvironmentsCourse) {
  RolloutBatch batch(settings(false));
  const SharedParams theta = share(std::vector<double>(kParamCount, 0.5));
  batch.add_evaluation(theta, rough(1.0, 9), 1);
  const size_t step = batch.add_es_step({theta, rough(2.0, 7), 0.05, 42}, 3);
  ASSERT_EQ(batch.size(), 1u + 6u);

  ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(double(i)); });
  RunCounters counters;
  batch.run(ev, counters);
  EXPECT_EQ(counters.rollouts, 7);
  EXPECT_EQ(counters.env_steps, 70);

  const auto& tasks = ev.batches[0];
  EXPECT_FALSE(tasks[0].perturbation);
  EXPECT_EQ(tasks[0].max_steps, 123);
  std::vector<uint64_t> keys;
  for (size_t i = 0; i < 3; ++i) {
    const RolloutTask& plus = tasks[1 + 2 * i];
    const RolloutTask& minus = tasks[2 + 2 * i];
    ASSERT_TRUE(plus.perturbation && minus.perturbation);
    EXPECT_EQ(plus.perturbation->key, minus.perturbation->key);
    EXPECT_EQ(plus.perturbation->sign, 1);
    EXPECT_EQ(minus.perturbation->sign, -1);
    EXPECT_EQ(plus.perturbation->sigma, 0.05);
    EXPECT_EQ(plus.env.seed, 7u);              // the environment's own course
    EXPECT_EQ(plus.theta.get(), theta.get());  // θ shared, not copied per task
    keys.push_back(plus.perturbation->key);
  }
  EXPECT_EQ(std::set<uint64_t>(keys.begin(), keys.end()).size(), 3u);

  // the gradient is es_gradient of the slice's returns (1..6 here), with the batch's keys
  const EsOutcome out = batch.es_outcome(step, EsSettings{});
  const std::vector<double> plus = {1, 3, 5}, minus = {2, 4, 6};
  EXPECT_EQ(out.gradient, es_gradient(keys, plus, minus, 0.05, true, kParamCount));
  EXPECT_DOUBLE_EQ(out.mean_return, 3.5);
  EXPECT_EQ(out.max_return, 6);
}

TEST(RolloutBatch, OutcomesOnAllCoresAreTheSerialOnesBitForBit) {
  RolloutBatch batch(settings(false));
  std::vector<size_t> handles;
  for (int s = 0; s < 7; ++s)
    handles.push_back(batch.add_es_step({share(std::vector<double>(kParamCount, 0.1 * s)), rough(1.0 + s, 7),
                                         0.02 + 0.01 * s, static_cast<uint64_t>(100 + s)},
                                        5));
  ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(double((i * 7919) % 101)); });
  RunCounters counters;
  batch.run(ev, counters);
  const std::vector<EsOutcome> all = batch.es_outcomes(handles, EsSettings{});
  ASSERT_EQ(all.size(), handles.size());
  for (size_t k = 0; k < handles.size(); ++k) {
    const EsOutcome one = batch.es_outcome(handles[k], EsSettings{});
    EXPECT_EQ(all[k].gradient, one.gradient) << k;
    EXPECT_EQ(all[k].mean_return, one.mean_return) << k;
    EXPECT_EQ(all[k].max_return, one.max_return) << k;
  }
}

TEST(RolloutBatch, StochasticEnvironmentsDrawCoursesPerMirroredPairAndPerEpisode) {
  RolloutBatch batch(settings(true));
  const SharedParams theta = share(std::vector<double>(kParamCount, 0.5));
  batch.add_es_step({theta, rough(2.0, 7), 0.05, 42}, 4);
  const size_t eval = batch.add_evaluation(theta, rough(2.0, 7), 99);
  ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(10.0 * double(i), i != 9); });
  RunCounters counters;
  batch.run(ev, counters);
  const auto& tasks = ev.batches[0];
  ASSERT_EQ(tasks.size(), 8u + 3u);
  std::set<uint32_t> seeds;
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(tasks[2 * i].env.seed, tasks[2 * i + 1].env.seed);  // a mirrored pair shares its course
    seeds.insert(tasks[2 * i].env.seed);
  }
  for (size_t e = 8; e < 11; ++e) seeds.insert(tasks[e].env.seed);
  EXPECT_EQ(seeds.size(), 7u);  // every pair and every evaluation episode on its own course

  const Evaluation ev_out = batch.evaluation(eval);  // episodes 8, 9, 10 → 80, 90, 100; 9 did not finish
  EXPECT_DOUBLE_EQ(ev_out.score, 90);
  EXPECT_FALSE(ev_out.finished);
}

// ES alone's domain randomisation: every mirrored pair and every evaluation episode on a course of its own, each
// drawn at the level asked for, the pair's members on the same one; the same keys give the same courses.
TEST(RolloutBatch, DomainRandomisationDrawsAnEncodingAtTheLevelPerMirroredPairAndPerEpisode) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::ES_ALONE);
  c.mutable_es_alone()->set_random_courses(pb::EsAloneConfig::VERY_CHALLENGING_COURSES);
  c.mutable_walker()->set_eval_episodes(3);
  const EpisodeSettings randomised = run_settings(c).episodes;
  ASSERT_EQ(randomised.random_courses, Difficulty::kVeryChallenging);
  EXPECT_TRUE(randomised.stochastic);
  EXPECT_EQ(randomised.eval_episodes, 3);

  const auto tasks_of = [&](const EpisodeSettings& settings) {
    RolloutBatch batch(settings);
    const SharedParams theta = share(std::vector<double>(kParamCount, 0.5));
    batch.add_es_step({theta, rough(2.0, 7), 0.05, 42}, 4);
    batch.add_evaluation(theta, rough(2.0, 7), 99);
    ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(double(i)); });
    RunCounters counters;
    batch.run(ev, counters);
    return ev.batches[0];
  };
  const std::vector<RolloutTask> tasks = tasks_of(randomised);
  ASSERT_EQ(tasks.size(), 8u + 3u);
  std::set<double> roughness;
  for (size_t i = 0; i < tasks.size(); ++i) {
    EXPECT_EQ(difficulty(tasks[i].env.encoding), Difficulty::kVeryChallenging) << i;
    EXPECT_EQ(validate(tasks[i].env.encoding), std::nullopt) << i;
    roughness.insert(tasks[i].env.encoding.roughness);
  }
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(tasks[2 * i].env.encoding.same_genes(tasks[2 * i + 1].env.encoding));
    EXPECT_EQ(tasks[2 * i].env.seed, tasks[2 * i + 1].env.seed);
  }
  EXPECT_EQ(roughness.size(), 7u) << "four pairs and three episodes, each on an encoding of its own";
  const std::vector<RolloutTask> again = tasks_of(randomised);
  for (size_t i = 0; i < tasks.size(); ++i) EXPECT_TRUE(tasks[i].env.encoding.same_genes(again[i].env.encoding));
  // the seeds are those of stochastic courses on the target's encoding: the encoding is drawn after the seed
  const std::vector<RolloutTask> stochastic = tasks_of(settings(true));
  for (size_t i = 0; i < tasks.size(); ++i) EXPECT_EQ(tasks[i].env.seed, stochastic[i].env.seed);
}

TEST(RolloutBatch, AnEmptyBatchNeverReachesTheEvaluatorAndBadResultsAreRefused) {
  RolloutBatch empty(settings(false));
  ScriptedEvaluator ev([](int, size_t, const RolloutTask&) { return scored(1); });
  RunCounters counters;
  empty.run(ev, counters);
  EXPECT_TRUE(ev.batches.empty());

  RolloutBatch batch(settings(false));
  batch.add_evaluation(share(std::vector<double>(kParamCount, 0.0)), rough(0.0), 1);
  ScriptedEvaluator nan([](int, size_t, const RolloutTask&) { return scored(std::nan("")); });
  EXPECT_THROW(batch.run(nan, counters), std::runtime_error);
}

// ES steps of 40 perturbations between evaluations, as transfer rounds lay them out.
RolloutBatch mixed_batch(std::vector<size_t>& es_handles) {
  RolloutBatch batch(settings(false));
  for (int s = 0; s < 6; ++s) {
    const SharedParams theta = share(std::vector<double>(kParamCount, 0.05 * s));
    batch.add_evaluation(theta, rough(1.0 + s, 7), static_cast<uint64_t>(s));
    es_handles.push_back(batch.add_es_step({theta, rough(1.0 + s, 7), 0.03 + 0.01 * s, 200u + s}, 40));
  }
  return batch;
}

TEST(RolloutBatch, OutcomesComputedAsResultsArriveAreTheSerialOnesBitForBit) {
  std::vector<size_t> handles;
  RolloutBatch batch = mixed_batch(handles);
  PiecemealEvaluator ev(hashed);
  RunCounters counters;
  batch.run(ev, counters, EsSettings{});
  EXPECT_EQ(counters.rollouts, static_cast<int64_t>(batch.size()));
  const std::vector<EsOutcome> early = batch.es_outcomes(handles, EsSettings{});
  ASSERT_EQ(early.size(), handles.size());
  for (size_t k = 0; k < handles.size(); ++k) EXPECT_TRUE(same_bits(early[k], batch.es_outcome(handles[k], {}))) << k;

  // the same batch run the old way, results arriving all at once
  std::vector<size_t> late_handles;
  RolloutBatch late = mixed_batch(late_handles);
  ScriptedEvaluator all_at_once([](int, size_t i, const RolloutTask&) { return hashed(i); });
  late.run(all_at_once, counters);
  const std::vector<EsOutcome> after = late.es_outcomes(late_handles, EsSettings{});
  for (size_t k = 0; k < handles.size(); ++k) EXPECT_TRUE(same_bits(early[k], after[k])) << k;

  // outcomes asked for other settings than those computed early are computed afresh
  EsSettings raw;
  raw.normalize_grads_by_sigma = false;
  const std::vector<EsOutcome> unnormalised = batch.es_outcomes(handles, raw);
  for (size_t k = 0; k < handles.size(); ++k)
    EXPECT_TRUE(same_bits(unnormalised[k], batch.es_outcome(handles[k], raw))) << k;
  EXPECT_FALSE(same_bits(unnormalised[0], early[0]));
}

TEST(RolloutBatch, AnEvaluatorThatThrowsMidBatchLeavesNoGradientRunning) {
  for (int reported : {0, 3, 60, 110}) {
    std::vector<size_t> handles;
    auto batch = std::make_unique<RolloutBatch>(mixed_batch(handles));
    PiecemealEvaluator ev(hashed, reported);  // 60 pieces or more complete ES steps, whose gradients then start
    RunCounters counters;
    EXPECT_THROW(batch->run(ev, counters, EsSettings{}), std::runtime_error) << reported;
    batch.reset();  // nothing may still read it
  }
}

TEST(RolloutBatch, ResultsReportedEarlyAreCheckedLikeTheOthers) {
  std::vector<size_t> handles;
  RolloutBatch nan_batch = mixed_batch(handles);
  PiecemealEvaluator nan([](size_t i) { return i == 5 ? scored(std::nan("")) : hashed(i); });
  RunCounters counters;
  EXPECT_THROW(nan_batch.run(nan, counters, EsSettings{}), std::runtime_error);

  // a return reported final and then returned changed
  class Fickle final : public Evaluator {
   public:
    using Evaluator::evaluate;
    std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
      std::vector<RolloutResult> out;
      for (size_t i = 0; i < tasks.size(); ++i) out.push_back(hashed(i));
      ready(0, out);
      out[7].total_reward += 1;
      return out;
    }
  } fickle;
  RolloutBatch batch = mixed_batch(handles);
  EXPECT_THROW(batch.run(fickle, counters, EsSettings{}), std::runtime_error);
}

}  // namespace
}  // namespace poet::testing
