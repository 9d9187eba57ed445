// Step 1 of the loop against a scripted evaluator: eligibility, the minimal criterion's bounds, de-duplication
// against the archive, ranking, admission through the best start, the cap and retirement.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine_test_support.h"
#include "scripted_evaluator.h"
#include "simulation/envgen/env_distance.h"

namespace poet::testing {
namespace {

// Unperturbed rollouts score `plain`, perturbed ones 0.
ScriptedEvaluator::Script constant(double plain) {
  return [plain](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0.0 : plain); };
}

bool is_mc_batch(const std::vector<RolloutTask>& batch) {
  return !batch.empty() && std::none_of(batch.begin(), batch.end(), [](const auto& t) { return t.perturbation; });
}

TEST(Reproduction, OnlyPairsAtTheThresholdAreParents) {
  pb::RunConfig c = tiny_config();
  RunState s = state_at(c, 4, 150);
  const Pair& eligible = add_pair(s, rough(1.0), 200);  // exactly the threshold counts
  const std::vector<double> parent_theta = eligible.theta;
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);

  ASSERT_TRUE(is_mc_batch(ev.batches[0]));
  ASSERT_EQ(ev.batches[0].size(), 6u);
  for (const RolloutTask& t : ev.batches[0]) {
    EXPECT_EQ(*t.theta, parent_theta);                 // the parent's current θ on each child
    EXPECT_GE(t.env.encoding.roughness, 0.4 - 1e-12);  // children of r = 1.0 move by at most 0.6
    EXPECT_LE(t.env.encoding.roughness, 1.6 + 1e-12);
  }
  EXPECT_EQ(events_named(r, "reproduction").at(0)["eligible"], 1);
}

TEST(Reproduction, NoEligibleParentMeansNoChildren) {
  RunState s = state_at(tiny_config(), 4, 199.9);
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 2u);  // the ES step and its evaluation only
  EXPECT_TRUE(ev.batches[0][0].perturbation);
  EXPECT_EQ(events_named(r, "reproduction").at(0)["eligible"], 0);
  EXPECT_EQ(s.counters.children_tried, 0);
}

// poet.reproduction_agent BEST_THETA: a pair whose walker an ES step broke (latest score below the threshold) is
// eligible by its best score, and its best θ is evaluated on the children, tried in the admission walk (direct and
// as a proposal's start) and given to the admitted child.
TEST(Reproduction, TheBestThetaCanBeThePairsAgent) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_reproduction_agent(pb::BEST_THETA);
  RunState s = state_at(c, 4, 120);  // latest 120: not eligible by its current θ
  Pair& parent = s.pairs[0];
  parent.best_score = 250;
  parent.best_theta = parent.theta;
  for (double& v : parent.best_theta) v += 0.25;
  const std::vector<double> best = parent.best_theta;
  const std::vector<double> current = parent.theta;
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 100); });
  const IterationReport r = run_iteration(s, ev);
  EXPECT_EQ(events_named(r, "reproduction").at(0)["eligible"], 1);
  ASSERT_TRUE(is_mc_batch(ev.batches[0]));
  for (const RolloutTask& t : ev.batches[0]) EXPECT_EQ(*t.theta, best);  // the minimal criterion
  for (const RolloutTask& t : ev.batches[1]) EXPECT_EQ(*t.theta, best);  // the walk's direct start
  for (const RolloutTask& t : ev.batches[2]) {                           // the proposal's ES step around it
    ASSERT_TRUE(t.perturbation);
    EXPECT_EQ(*t.theta, best);
  }
  ASSERT_EQ(s.pairs.size(), 2u);
  EXPECT_EQ(s.pairs[1].initial_source_pair, 0);
  EXPECT_FALSE(s.pairs[1].initial_by_proposal);  // ties go to the direct start: the best θ itself
  EXPECT_EQ(s.pairs[1].best_theta, best);
  EXPECT_EQ(s.pairs[0].theta.size(), current.size());  // ES goes on from the current θ
  // with the default (CURRENT_THETA) the same pair is no parent
  c.mutable_poet()->clear_reproduction_agent();
  RunState t = state_at(c, 4, 120);
  t.pairs[0].best_score = 250;
  ScriptedEvaluator plain([](int, size_t, const RolloutTask& task) { return scored(task.perturbation ? 0 : 100); });
  EXPECT_EQ(events_named(run_iteration(t, plain), "reproduction").at(0)["eligible"], 0);
}

TEST(Reproduction, OnlyOnMultiplesOfTheInterval) {
  RunState s = state_at(tiny_config(), 5, 250);
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);
  EXPECT_EQ(ev.batches.size(), 2u);
  EXPECT_TRUE(events_named(r, "reproduction").empty());
}

TEST(Reproduction, MinimalCriterionKeepsBothBoundsInclusive) {
  RunState s = state_at(tiny_config(), 4, 250);
  const std::vector<double> mc_scores = {49.99, 50, 300, 300.01, 100, -5};
  ScriptedEvaluator ev([&](int call, size_t i, const RolloutTask& t) {
    if (call == 0) return scored(mc_scores.at(i));
    return scored(t.perturbation ? 0.0 : 100.0);
  });
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(ev.batches[0].size(), 6u);
  EXPECT_EQ(s.counters.children_tried, 6);
  EXPECT_EQ(s.counters.children_passed_mc, 3);  // 50, 300 and 100
  EXPECT_EQ(events_named(r, "reproduction").at(0)["passed_mc"], 3);
  // one "child" event per attempt, in attempt order, with its MC score, verdict and 5-vector
  const auto children = events_named(r, "child");
  ASSERT_EQ(children.size(), 6u);
  for (size_t i = 0; i < children.size(); ++i) {
    EXPECT_EQ(children[i]["attempt"], i);
    EXPECT_EQ(children[i]["mc_score"], mc_scores[i]);
    EXPECT_EQ(children[i]["passed_mc"], i == 1 || i == 2 || i == 4);
    EXPECT_EQ(children[i]["e"].size(), 5u);
    EXPECT_EQ(children[i]["env"], ev.batches[0][i].env.encoding.name);
  }
}

TEST(Reproduction, ChildrenEqualToAnyArchivedEnvironmentAreDropped) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->mutable_mutation()->set_pits(false);
  c.mutable_poet()->mutable_mutation()->set_stumps(false);
  RunState s = state_at(c, 4, 250);
  // flat's roughness-only children are r ∈ {0.0, …, 0.6}: all archived, r > 0 by retired pairs
  for (int k = 1; k <= 6; ++k) add_pair(s, rough(k / 10.0), 0).retired_iteration = 1;
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);
  EXPECT_FALSE(is_mc_batch(ev.batches[0]));  // nothing left to evaluate
  EXPECT_EQ(s.counters.children_tried, 6);
  EXPECT_EQ(events_named(r, "reproduction").at(0)["duplicates"], 6);
  for (const auto& child : events_named(r, "child")) {
    EXPECT_TRUE(child["duplicate"]);
    EXPECT_FALSE(child.contains("mc_score"));
  }
  EXPECT_EQ(s.pairs.size(), 7u);
}

// The novelty ranking the spec asks for, computed here from the children the loop evaluated.
std::vector<EnvDef> novelty_ranking(const std::vector<RolloutTask>& mc_batch, const RunState& before, int k) {
  std::vector<EnvEncoding> archive;
  for (const Pair& p : before.pairs) archive.push_back(p.env.encoding);
  std::vector<std::pair<double, EnvDef>> ranked;
  for (const RolloutTask& t : mc_batch) ranked.push_back({novelty(t.env.encoding, archive, k), t.env});
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<EnvDef> out;
  for (auto& [n, env] : ranked) out.push_back(env);
  return out;
}

TEST(Reproduction, AdmitsInNoveltyOrderMostNovelFirst) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(10);
  RunState s = state_at(c, 4, 250);
  add_pair(s, rough(2.0), 0);
  const RunState before = s;
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);

  const std::vector<EnvDef> ranking = novelty_ranking(ev.batches[0], before, 5);
  const auto created = events_named(r, "pair_created");
  ASSERT_GE(created.size(), 2u);
  double previous = 1e300;
  for (const auto& e : created) {
    EXPECT_LE(e["novelty"].get<double>(), previous);
    previous = e["novelty"].get<double>();
  }
  // the new pairs are the ranking with later duplicates of an admitted child skipped
  std::vector<EnvDef> expected;
  for (const EnvDef& env : ranking)
    if (std::none_of(expected.begin(), expected.end(),
                     [&](const EnvDef& x) { return x.encoding.same_genes(env.encoding); }))
      expected.push_back(env);
  ASSERT_EQ(s.pairs.size(), 2 + expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_TRUE(s.pairs[2 + i].env.encoding.same_genes(expected[i].encoding)) << i;
    EXPECT_EQ(s.pairs[2 + i].env.seed, expected[i].seed);
    EXPECT_EQ(s.pairs[2 + i].created_iteration, 4);
    EXPECT_EQ(s.pairs[2 + i].parent_id, 0);
  }
  EXPECT_EQ(s.counters.children_admitted, static_cast<int64_t>(expected.size()));
}

TEST(Reproduction, LowestScoreFirstIsAnOption) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_child_ranking(pb::LOWEST_SCORE_FIRST);
  RunState s = state_at(c, 4, 250);
  const std::vector<double> mc_scores = {200, 60, 150, 100, 250, 80};
  ScriptedEvaluator ev([&](int call, size_t i, const RolloutTask& t) {
    if (call == 0) return scored(mc_scores.at(i));
    return scored(t.perturbation ? 0.0 : 100.0);
  });
  run_iteration(s, ev);
  ASSERT_EQ(s.pairs.size(), 2u);
  EXPECT_TRUE(s.pairs[1].env.encoding.same_genes(ev.batches[0][1].env.encoding));  // the child that scored 60
}

// PATA-EC novelty (Enhanced POET): a run whose agents are three pairs' θs — the eligible flat pair, an active
// pair on r2 and a retired one on r3.
struct PataEcRun {
  RunState state;
  std::vector<std::vector<double>> agents;  // the pairs' θs, in creation order

  explicit PataEcRun(int max_admitted, int max_children = 6)
      : state(state_at(pata_ec_config(max_admitted, max_children), 4, 250)) {
    add_pair(state, rough(2.0), 0);
    add_pair(state, rough(3.0), 0).retired_iteration = 2;
    for (const Pair& p : state.pairs) agents.push_back(p.theta);
  }
  static pb::RunConfig pata_ec_config(int max_admitted, int max_children) {
    pb::RunConfig c = tiny_config();
    c.mutable_poet()->set_novelty(pb::PATA_EC);
    c.mutable_poet()->set_max_admitted(max_admitted);
    c.mutable_poet()->set_max_children(max_children);
    c.set_seed(4);  // its first three children differ in genes, which the ranking test needs
    return c;
  }
  size_t agent(const RolloutTask& t) const {
    return static_cast<size_t>(std::find(agents.begin(), agents.end(), *t.theta) - agents.begin());
  }
};

bool same_env(const EnvDef& a, const EnvDef& b) { return a.encoding.same_genes(b.encoding) && a.seed == b.seed; }

TEST(Reproduction, PataEcCharacterisesOnlyTheChildrenThatPassTheCriterion) {
  PataEcRun run(0);
  const std::vector<double> mc_scores = {49, 100, 301, 120, 10, 200};  // children 1, 3 and 5 pass
  ScriptedEvaluator ev([&](int call, size_t i, const RolloutTask& t) {
    if (call == 0) return scored(mc_scores.at(i));
    return scored(t.perturbation ? 0.0 : 100.0);
  });
  const IterationReport r = run_iteration(run.state, ev);
  ASSERT_EQ(ev.batches[0].size(), 6u);
  // one batch: each of the 3 agents (the retired one too) on the 3 archived environments and the 3 passing children
  const std::vector<RolloutTask>& pata = ev.batches.at(1);
  ASSERT_EQ(pata.size(), (3u + 3u) * 3u);
  std::vector<EnvDef> environments;
  for (size_t p = 0; p < 3; ++p) environments.push_back(run.state.pairs[p].env);
  for (size_t c : {1, 3, 5}) environments.push_back(ev.batches[0][c].env);
  for (size_t e = 0; e < environments.size(); ++e) {
    for (size_t a = 0; a < 3; ++a) {
      const RolloutTask& t = pata[e * 3 + a];
      EXPECT_FALSE(t.perturbation);
      EXPECT_TRUE(same_env(t.env, environments[e])) << e;
      EXPECT_EQ(run.agent(t), a) << e;
    }
  }
  EXPECT_EQ(events_named(r, "reproduction").at(0)["pata_ec_evaluations"], 18);
  // the evaluations count as rollouts like any batch's
  size_t tasks = 0;
  for (const auto& batch : ev.batches) tasks += batch.size();
  EXPECT_EQ(run.state.counters.rollouts, static_cast<int64_t>(tasks));
}

TEST(Reproduction, PataEcCostsNothingWhenNoChildPasses) {
  PataEcRun run(1);
  ScriptedEvaluator ev([](int call, size_t, const RolloutTask& t) {
    if (call == 0) return scored(10);  // below mc_low
    return scored(t.perturbation ? 0.0 : 100.0);
  });
  const IterationReport r = run_iteration(run.state, ev);
  ASSERT_EQ(ev.batches.size(), 3u);  // the MC batch, then the ES step and its evaluation
  EXPECT_TRUE(ev.batches[1].at(0).perturbation);
  EXPECT_EQ(events_named(r, "reproduction").at(0)["pata_ec_evaluations"], 0);
}

// Three children given three score profiles over the agents (0, 1, 2), against an archive on which the agents
// score 60, 70, 80 (PATA-EC (−1/2, 0, 1/2)):
// - (30, 20, 10): all clipped to mc_low 50, so tied and ranked in agent order (−1/2, 0, 1/2): novelty 0
//   (unclipped it would be the most novel);
// - (400, 290, 10) → (300, 290, 50): (1/2, 0, −1/2), √2 from each archived PATA-EC;
// - (70, 60, 80): (0, −1/2, 1/2), √(1/4 + 1/4) = √(1/2) from each.
// Whichever child gets which profile, admission walks them most novel first.
TEST(Reproduction, PataEcRankingFollowsHowTheAgentsRankOnTheChildren) {
  const std::vector<std::vector<double>> profiles = {{30, 20, 10}, {400, 290, 10}, {70, 60, 80}};
  const std::vector<double> novelties = {0, std::sqrt(2.0), std::sqrt(0.5)};
  for (size_t rotation = 0; rotation < 3; ++rotation) {
    PataEcRun run(3, 3);
    std::vector<RolloutTask> children;  // the MC batch
    ScriptedEvaluator ev([&](int call, size_t, const RolloutTask& t) {
      if (call == 0) {
        children.push_back(t);
        return scored(100);
      }
      if (call != 1) return scored(t.perturbation ? 0.0 : 100.0);
      const size_t a = run.agent(t);
      for (size_t c = 0; c < children.size(); ++c)
        if (same_env(t.env, children[c].env)) return scored(profiles[(c + rotation) % 3].at(a));
      return scored(60.0 + 10.0 * static_cast<double>(a));  // an archived environment
    });
    const IterationReport r = run_iteration(run.state, ev);
    SCOPED_TRACE("rotation " + std::to_string(rotation));
    ASSERT_EQ(children.size(), 3u);
    for (size_t c = 0; c < 3; ++c)  // distinct children
      ASSERT_FALSE(children[c].env.encoding.same_genes(children[(c + 1) % 3].env.encoding))
          << children[c].env.encoding.name;
    // admitted most novel first: profile 1, then 2, then 0
    ASSERT_EQ(run.state.pairs.size(), 6u);
    const auto created = events_named(r, "pair_created");
    ASSERT_EQ(created.size(), 3u);
    const std::vector<size_t> order = {1, 2, 0};
    for (size_t k = 0; k < 3; ++k) {
      const size_t child = (order[k] + 3 - rotation) % 3;  // the child that got profile order[k]
      EXPECT_TRUE(same_env(run.state.pairs[3 + k].env, children[child].env)) << k;
      EXPECT_NEAR(created[k]["novelty"].get<double>(), novelties[order[k]], 1e-12) << k;
    }
  }
}

TEST(Reproduction, AdmissionNeedsTheBestStartToPassTheCriterionAndStopsAtTheCap) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(1);
  RunState s = state_at(c, 4, 250);
  const RunState before = s;
  // the first candidate's direct starts score above mc_high; the second candidate's pass
  ScriptedEvaluator ev([](int call, size_t, const RolloutTask& t) {
    if (t.perturbation) return scored(0);
    if (call == 1) return scored(301);
    return scored(100);
  });
  const IterationReport r = run_iteration(s, ev);
  const std::vector<EnvDef> ranking = novelty_ranking(ev.batches[0], before, 5);
  ASSERT_EQ(s.pairs.size(), 2u);
  EXPECT_EQ(events_named(r, "pair_created").size(), 1u);
  ASSERT_FALSE(ranking[0].encoding.same_genes(ranking[1].encoding));
  EXPECT_TRUE(s.pairs[1].env.encoding.same_genes(ranking[1].encoding));
  // walks: MC batch; the first candidate's direct evaluations, which refuse it without proposal steps; the
  // second's direct evaluations, proposal ES steps and proposal evaluations; then the ES step and evaluation
  ASSERT_EQ(ev.batches.size(), 7u);
  for (const size_t b : {1, 2}) {
    for (const RolloutTask& t : ev.batches[b]) {
      EXPECT_FALSE(t.perturbation) << b;
      EXPECT_TRUE(t.env.encoding.same_genes(ranking[b - 1].encoding)) << b;
    }
  }
  EXPECT_TRUE(ev.batches[3].at(0).perturbation);
}

// A candidate whose direct starts pass but whose best proposal scores above mc_high is refused after the
// proposals: the screen on direct scores changes no outcome.
TEST(Reproduction, AProposalAboveTheCriterionRefusesTheCandidateToo) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_max_children(1);
  RunState s = state_at(c, 4, 250);
  ScriptedEvaluator ev([](int call, size_t, const RolloutTask& t) {
    if (t.perturbation) return scored(0);
    if (call == 3) return scored(301);  // the proposal's evaluation
    return scored(100);
  });
  const IterationReport r = run_iteration(s, ev);
  EXPECT_EQ(s.pairs.size(), 1u);
  EXPECT_TRUE(events_named(r, "pair_created").empty());
  ASSERT_EQ(ev.batches.size(), 6u);  // MC, direct, proposal ES, proposal evaluation, then ES step and evaluation
  EXPECT_TRUE(ev.batches[2].at(0).perturbation);
}

TEST(Reproduction, BestStartPrefersTheHighestScoreAndTheFirstOnTies) {
  for (const bool tie : {false, true}) {
    pb::RunConfig c = tiny_config();
    c.mutable_poet()->set_max_admitted(1);
    RunState s = state_at(c, 4, 250);
    const Pair& other = add_pair(s, rough(3.0), 0);
    const std::vector<double> theta0 = s.pairs[0].theta, theta1 = other.theta;
    // call 1: direct evaluations (θ0 → 60, θ1 → 80); call 2: the proposals' ES; call 3: proposals (70 and 90)
    ScriptedEvaluator ev([&](int call, size_t i, const RolloutTask& t) {
      if (t.perturbation) return scored(0);
      if (tie) return scored(60);
      if (call == 1) return scored(*t.theta == theta0 ? 60 : 80);
      if (call == 3) return scored(i == 0 ? 70 : 90);
      return scored(100);
    });
    run_iteration(s, ev);
    ASSERT_EQ(s.pairs.size(), 3u);
    const Pair& child = s.pairs[2];
    if (tie) {
      EXPECT_EQ(child.initial_source_pair, 0);
      EXPECT_FALSE(child.initial_by_proposal);
      EXPECT_EQ(child.admission_score, 60);
    } else {
      EXPECT_EQ(child.initial_source_pair, 1);
      EXPECT_TRUE(child.initial_by_proposal);
      EXPECT_EQ(child.admission_score, 90);
      EXPECT_EQ(ev.batches[3].at(1).theta->size(), static_cast<size_t>(kParamCount));
      EXPECT_NE(*ev.batches[3].at(1).theta, theta1);  // a proposal, not θ1 itself
    }
    EXPECT_EQ(child.optimizer.t, 1);  // a fresh optimizer, then its first ES step this iteration
    EXPECT_EQ(child.es_steps, 1);
  }
}

TEST(Reproduction, TheOldestActivePairsRetireBeyondTheCap) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_active_cap(2);
  RunState s = state_at(c, 4, 250);
  add_pair(s, rough(3.0), 0);
  ScriptedEvaluator ev(constant(100));
  const IterationReport r = run_iteration(s, ev);
  ASSERT_EQ(s.pairs.size(), 3u);  // retired pairs stay in the archive
  EXPECT_EQ(s.pairs[0].retired_iteration, 4);
  EXPECT_TRUE(s.pairs[1].active());
  EXPECT_TRUE(s.pairs[2].active());
  EXPECT_EQ(events_named(r, "pair_retired").at(0)["pair"], 0);
  // the retired pair takes no ES step: the optimisation batch holds two pairs' perturbations
  EXPECT_EQ(ev.batches[ev.batches.size() - 2].size(), 2u * 2 * 2);
  EXPECT_EQ(s.pairs[0].es_steps, 0);
}

}  // namespace
}  // namespace poet::testing
