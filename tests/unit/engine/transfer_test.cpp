// Step 3 of the loop against a scripted evaluator: direct and proposal transfers, acceptance only when strictly
// better, ties to the first in order, θs from before the round, optimizer reset, counters and lineage.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "engine_test_support.h"
#include "scripted_evaluator.h"

namespace poet::testing {
namespace {

// Two pairs (flat and roughness 1) about to run iteration 5 with transfers every 5 iterations.
RunState two_pairs() {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_mutation_interval(1000);
  c.mutable_poet()->set_transfer_interval(5);
  RunState s = state_at(c, 5, 0);
  add_pair(s, rough(1.0), 0);
  return s;
}

bool on_flat(const RolloutTask& t) { return t.env.encoding.roughness == 0; }

// Calls: 0 the ES steps, 1 their evaluations (both pairs 100), 2 direct transfers and the proposals' ES,
// 3 the proposals' evaluations.
ScriptedEvaluator transfer_script(double direct_on_flat, double direct_on_rough, double proposal_on_flat,
                                  double proposal_on_rough, bool finished = false) {
  return ScriptedEvaluator([=](int call, size_t, const RolloutTask& t) {
    if (t.perturbation) return scored(0);
    if (call == 2) return scored(on_flat(t) ? direct_on_flat : direct_on_rough, finished);
    if (call == 3) return scored(on_flat(t) ? proposal_on_flat : proposal_on_rough, finished);
    return scored(100);
  });
}

// confirm_transfers on stochastic courses: each target's choice and its θ run on the same fresh courses (call 4),
// and the choice stands only where it beats θ there, with that score.
TEST(Transfer, OnStochasticCoursesAChoiceMustBeatTheTargetsThetaAgainOnFreshCourses) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_mutation_interval(1000);
  c.mutable_poet()->set_transfer_interval(5);
  c.mutable_walker()->set_stochastic_envs(true);
  c.mutable_walker()->set_eval_episodes(2);
  c.mutable_poet()->set_confirm_transfers(true);
  RunState s = state_at(c, 5, 0);
  add_pair(s, rough(1.0), 0);
  // calls 0–3 as transfer_script(150, 100, 120, 200); call 4: pair 0's choice 90 against its θ's 95 (refused),
  // pair 1's choice 180 against its θ's 100 (kept)
  ScriptedEvaluator ev([](int call, size_t i, const RolloutTask& t) {
    if (t.perturbation) return scored(0);
    if (call == 2) return scored(on_flat(t) ? 150 : 100);
    if (call == 3) return scored(on_flat(t) ? 120 : 200);
    if (call == 4) return scored(std::array{90.0, 90.0, 95.0, 95.0, 180.0, 180.0, 100.0, 100.0}.at(i));
    return scored(100);
  });
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 5u);
  const std::vector<RolloutTask>& confirm = ev.batches[4];
  ASSERT_EQ(confirm.size(), 8u);  // per target: the choice's two episodes, then θ's two, on the same courses
  for (size_t target = 0; target < 2; ++target)
    for (size_t e = 0; e < 2; ++e) EXPECT_EQ(confirm[4 * target + e].env.seed, confirm[4 * target + 2 + e].env.seed);
  EXPECT_NE(confirm[0].env.seed, confirm[1].env.seed);
  EXPECT_EQ(s.pairs[0].theta, *confirm[2].theta) << "the choice lost to θ on the fresh courses";
  EXPECT_NE(*confirm[0].theta, *confirm[2].theta);
  EXPECT_EQ(s.pairs[1].theta, *confirm[4].theta) << "the choice beat θ on the fresh courses";
  EXPECT_TRUE(s.pairs[0].transfers.empty());
  ASSERT_EQ(s.pairs[1].transfers.size(), 1u);
  EXPECT_TRUE(s.pairs[1].transfers[0].proposal);
  EXPECT_EQ(s.pairs[1].transfers[0].score, 180);
  EXPECT_EQ(s.pairs[1].latest_score, 180) << "the score recorded is the confirmation's";
  EXPECT_EQ(s.counters.transfer_attempts, 2);
  EXPECT_EQ(s.counters.transfer_successes, 1);
  const auto rounds = events_named(r, "transfer_round");
  ASSERT_EQ(rounds.size(), 1u);
  EXPECT_EQ(rounds[0]["accepted"], 1);
  EXPECT_EQ(rounds[0]["unconfirmed"], 1);
}

TEST(Transfer, DirectAndProposalTransfersReplaceWhenStrictlyBetter) {
  RunState s = two_pairs();
  ScriptedEvaluator ev = transfer_script(150, 100, 120, 200);
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 4u);

  // θ1 as it stood before the round went to pair 0, directly
  std::vector<double> theta1_before;
  for (const RolloutTask& t : ev.batches[2])
    if (!t.perturbation && on_flat(t)) theta1_before = *t.theta;
  const Pair& p0 = s.pairs[0];
  EXPECT_EQ(p0.theta, theta1_before);
  EXPECT_EQ(p0.latest_score, 150);
  ASSERT_EQ(p0.transfers.size(), 1u);
  EXPECT_EQ(p0.transfers[0].source_pair, 1);
  EXPECT_FALSE(p0.transfers[0].proposal);
  EXPECT_EQ(p0.transfers[0].iteration, 5);

  // pair 1: the direct transfer only ties (100), the proposal wins
  const Pair& p1 = s.pairs[1];
  EXPECT_EQ(p1.latest_score, 200);
  ASSERT_EQ(p1.transfers.size(), 1u);
  EXPECT_TRUE(p1.transfers[0].proposal);
  EXPECT_EQ(*ev.batches[3].at(1).theta, p1.theta);

  // both optimizers are back to fresh
  for (const Pair& p : s.pairs) {
    EXPECT_EQ(p.optimizer.t, 0);
    EXPECT_EQ(p.optimizer.lr, s.settings.es.init_lr);
    EXPECT_EQ(p.optimizer.sigma, s.settings.es.init_sigma);
    EXPECT_EQ(p.optimizer.m, std::vector<double>(kParamCount, 0.0));
    EXPECT_EQ(p.transfer_attempts, 1);
    EXPECT_EQ(p.best_score, p.latest_score);
  }
  EXPECT_EQ(s.counters.transfer_attempts, 2);
  EXPECT_EQ(s.counters.transfer_successes, 2);
  EXPECT_EQ(events_named(r, "transfer").size(), 2u);
  const auto rounds = events_named(r, "transfer_round");
  ASSERT_EQ(rounds.size(), 1u);
  EXPECT_EQ(rounds[0]["test"], "full");
  EXPECT_EQ(rounds[0]["proposals"], 2);
  EXPECT_EQ(rounds[0]["accepted"], 2);
  // per candidate a direct evaluation, a proposal ES step of 2n rollouts and its evaluation: the round's batches
  const size_t n = static_cast<size_t>(s.settings.es.perturbations);
  EXPECT_EQ(rounds[0]["rollouts"], 2 * (2 * n + 2));
  EXPECT_EQ(rounds[0]["rollouts"], ev.batches[2].size() + ev.batches[3].size());
}

TEST(Transfer, EqualScoresDoNotReplace) {
  RunState s = two_pairs();
  const RunState before = s;
  ScriptedEvaluator ev = transfer_script(100, 100, 100, 100);
  run_iteration(s, ev);
  for (const Pair& p : s.pairs) {
    EXPECT_TRUE(p.transfers.empty());
    EXPECT_EQ(p.optimizer.t, 1);  // the iteration's own ES step, not reset
  }
  EXPECT_EQ(s.counters.transfer_attempts, 2);
  EXPECT_EQ(s.counters.transfer_successes, 0);
}

TEST(Transfer, DirectWinsATieWithAProposal) {
  RunState s = two_pairs();
  ScriptedEvaluator ev = transfer_script(150, 100, 150, 100);
  run_iteration(s, ev);
  ASSERT_EQ(s.pairs[0].transfers.size(), 1u);
  EXPECT_FALSE(s.pairs[0].transfers[0].proposal);
}

TEST(Transfer, ATransferredAgentCanSolve) {
  RunState s = two_pairs();
  ScriptedEvaluator ev = transfer_script(240, 100, 0, 0, /*finished=*/true);
  const IterationReport r = run_iteration(s, ev);
  EXPECT_EQ(s.pairs[0].first_solved_iteration, 5);
  EXPECT_FALSE(s.pairs[1].solved());
  EXPECT_EQ(events_named(r, "solved").size(), 1u);
}

TEST(Transfer, OnlyOnMultiplesOfTheIntervalAndWithTwoPairs) {
  RunState s = two_pairs();
  s.next_iteration = 6;
  ScriptedEvaluator ev = transfer_script(150, 150, 150, 150);
  run_iteration(s, ev);
  EXPECT_EQ(ev.batches.size(), 2u);
  EXPECT_EQ(s.counters.transfer_attempts, 0);
}

TEST(Transfer, ProposalsUseTheTargetsSigma) {
  RunState s = two_pairs();
  s.pairs[0].optimizer.sigma = 0.05;
  s.pairs[1].optimizer.sigma = 0.07;
  ScriptedEvaluator ev = transfer_script(0, 0, 0, 0);
  run_iteration(s, ev);
  for (const RolloutTask& t : ev.batches[2]) {
    if (!t.perturbation) continue;
    // σ after the iteration's own step decayed it once
    EXPECT_DOUBLE_EQ(t.perturbation->sigma, (on_flat(t) ? 0.05 : 0.07) * s.settings.es.sigma_decay);
  }
}

// ------------------------------------------------------------------ the threshold test (Enhanced POET's)

RunState two_pairs_threshold() {
  RunState s = two_pairs();
  s.settings.poet.transfer_test = TransferTest::kThreshold;
  return s;
}

// Calls: 0 the ES steps, 1 their evaluations (both pairs 100), 2 the direct transfers, 3 the ES steps of the
// sources that passed, 4 their proposals' evaluations.
ScriptedEvaluator threshold_script(double direct_on_flat, double direct_on_rough, double proposal_on_flat,
                                   double proposal_on_rough) {
  return ScriptedEvaluator([=](int call, size_t, const RolloutTask& t) {
    if (t.perturbation) return scored(0);
    if (call == 2) return scored(on_flat(t) ? direct_on_flat : direct_on_rough);
    if (call == 4) return scored(on_flat(t) ? proposal_on_flat : proposal_on_rough);
    return scored(100);
  });
}

size_t perturbations_in(const std::vector<RolloutTask>& batch) {
  return static_cast<size_t>(
      std::count_if(batch.begin(), batch.end(), [](const RolloutTask& t) { return t.perturbation.has_value(); }));
}

// Pair 0's threshold is the best of its last five scores (130, above its latest 100): a direct 120 does not pass
// and costs no ES step; pair 1's threshold is 100 and a direct 150 passes, and its proposal (180) replaces θ.
TEST(TransferThreshold, OnlySourcesAboveTheThresholdGetAProposalStep) {
  RunState s = two_pairs_threshold();
  s.pairs[0].recent_scores = {90, 130, 95, 100};
  s.pairs[1].recent_scores = {100};
  ScriptedEvaluator ev = threshold_script(120, 150, 500, 180);
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 5u);
  EXPECT_EQ(perturbations_in(ev.batches[2]), 0u);  // direct evaluations only
  EXPECT_EQ(perturbations_in(ev.batches[3]), 2u * static_cast<size_t>(s.settings.es.perturbations));
  for (const RolloutTask& t : ev.batches[3]) EXPECT_FALSE(on_flat(t));  // only pair 1's candidate
  ASSERT_EQ(ev.batches[4].size(), 1u);

  EXPECT_TRUE(s.pairs[0].transfers.empty());
  ASSERT_EQ(s.pairs[1].transfers.size(), 1u);
  EXPECT_TRUE(s.pairs[1].transfers[0].proposal);
  EXPECT_EQ(s.pairs[1].latest_score, 180);
  EXPECT_EQ(s.pairs[1].optimizer.t, 0);
  EXPECT_EQ(s.counters.transfer_attempts, 2);
  EXPECT_EQ(s.counters.transfer_successes, 1);
  EXPECT_EQ(events_named(r, "transfer").size(), 1u);
  const auto rounds = events_named(r, "transfer_round");
  ASSERT_EQ(rounds.size(), 1u);
  EXPECT_EQ(rounds[0]["test"], "threshold");
  EXPECT_EQ(rounds[0]["candidates"], 2);
  EXPECT_EQ(rounds[0]["proposals"], 1);
  EXPECT_EQ(rounds[0]["accepted"], 1);
  // two direct evaluations, then one proposal's ES step and evaluation
  EXPECT_EQ(rounds[0]["rollouts"], 2 + 2 * static_cast<size_t>(s.settings.es.perturbations) + 1);
  // the evaluations of the iteration (and the accepted transfer) joined the recent scores, at most five kept
  EXPECT_EQ(s.pairs[0].recent_scores, (std::vector<double>{90, 130, 95, 100, 100}));
  EXPECT_EQ(s.pairs[1].recent_scores, (std::vector<double>{100, 100, 180}));
}

// A source that passes directly but whose proposal does not beat the threshold replaces nothing, even when its
// direct score did: the threshold test accepts proposals only.
TEST(TransferThreshold, AProposalMustBeatTheThresholdToo) {
  RunState s = two_pairs_threshold();
  ScriptedEvaluator ev = threshold_script(150, 150, 100, 90);
  run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 5u);
  for (const Pair& p : s.pairs) EXPECT_TRUE(p.transfers.empty());
  EXPECT_EQ(s.counters.transfer_successes, 0);
}

// No source passes: no ES step and no proposal is paid for.
TEST(TransferThreshold, NothingAboveTheThresholdCostsOnlyTheDirectEvaluations) {
  RunState s = two_pairs_threshold();
  ScriptedEvaluator ev = threshold_script(100, 50, 500, 500);
  run_iteration(s, ev);
  EXPECT_EQ(ev.batches.size(), 3u);
  EXPECT_EQ(s.counters.transfer_attempts, 2);
  EXPECT_EQ(s.counters.transfer_successes, 0);
}

// The threshold is the best of the last five scores, the iteration's own evaluation included: a best score that
// has left the window no longer holds a source back. Pair 0's 300 is its sixth-latest once the iteration's 100
// joins, so its threshold is 100 and a direct 150 passes; pair 1's 300 is still fifth-latest and blocks a 150.
TEST(TransferThreshold, OnlyTheLastFiveScoresCount) {
  RunState s = two_pairs_threshold();
  s.pairs[0].recent_scores = {300, 90, 90, 90, 90};
  s.pairs[1].recent_scores = {90, 300, 90, 90, 90};
  ScriptedEvaluator ev = threshold_script(150, 150, 160, 500);
  run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 5u);
  for (const RolloutTask& t : ev.batches[3]) EXPECT_TRUE(on_flat(t));  // only pair 0's candidate is fine-tuned
  ASSERT_EQ(s.pairs[0].transfers.size(), 1u);
  EXPECT_EQ(s.pairs[0].latest_score, 160);
  EXPECT_TRUE(s.pairs[1].transfers.empty());
}

// The full test keeps no recent scores, so its states (and the golden digests) are those of before the option.
TEST(TransferThreshold, TheFullTestKeepsNoRecentScores) {
  RunState s = two_pairs();
  ScriptedEvaluator ev = transfer_script(150, 100, 120, 200);
  run_iteration(s, ev);
  for (const Pair& p : s.pairs) EXPECT_TRUE(p.recent_scores.empty());
}

}  // namespace
}  // namespace poet::testing
