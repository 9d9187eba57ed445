// The paper's controls as modes of the engine: ES alone, POET without transfer, the direct-path curriculum; and
// ES improving a synthetic objective through the engine's own ES path.

#include <gtest/gtest.h>

#include <cmath>

#include "common/formats/envgen/env_proto.h"
#include "engine/curriculum.h"
#include "engine/state_consistency.h"
#include "engine_test_support.h"
#include "scripted_evaluator.h"
#include "simulation/es/perturbation.h"

namespace poet::testing {
namespace {

TEST(InitialState, AStartThetaReplacesTheInitStreamInEveryMode) {
  const std::vector<double> theta(kParamCount, 0.25);
  for (auto mode : {pb::RunConfig::POET, pb::RunConfig::ES_ALONE, pb::RunConfig::POET_WITHOUT_TRANSFER}) {
    pb::RunConfig c = tiny_config();
    c.set_mode(mode);
    if (mode == pb::RunConfig::ES_ALONE) *c.mutable_es_alone()->mutable_target() = to_proto(rough(1.0, 3));
    const RunState from_file = initial_state(run_settings(c), theta);
    const RunState random = initial_state(run_settings(c));
    ASSERT_EQ(from_file.pairs.size(), 1u);
    EXPECT_EQ(from_file.pairs[0].theta, theta);
    EXPECT_EQ(from_file.pairs[0].best_theta, theta);
    EXPECT_NE(random.pairs[0].theta, theta);
    EXPECT_EQ(from_file.pairs[0].env.encoding.name, random.pairs[0].env.encoding.name) << "only θ changes";
    EXPECT_EQ(from_file.pairs[0].env.seed, random.pairs[0].env.seed);
    EXPECT_EQ(from_file.pairs[0].optimizer.t, 0);
  }
}

TEST(EsAlone, OptimisesOnePairOnTheTargetAndNeverReproducesOrTransfers) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::ES_ALONE);
  c.mutable_poet()->set_mutation_interval(1);
  c.mutable_poet()->set_transfer_interval(1);
  *c.mutable_es_alone()->mutable_target() = to_proto(rough(2.5, 77));
  RunState s = initial_state(run_settings(c));
  ASSERT_EQ(s.pairs.size(), 1u);
  EXPECT_EQ(s.pairs[0].env.encoding.roughness, 2.5);
  EXPECT_EQ(s.pairs[0].env.seed, 77u);
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 300); });
  for (int i = 0; i < 3; ++i) run_iteration(s, ev);
  EXPECT_EQ(ev.batches.size(), 6u);  // an ES step and an evaluation per iteration, nothing else
  EXPECT_EQ(s.pairs.size(), 1u);
  EXPECT_EQ(s.pairs[0].es_steps, 3);
  // the pair's environment steps are every rollout's of the run: its ES steps and their evaluations
  EXPECT_EQ(s.pairs[0].es_env_steps, s.counters.env_steps);
  EXPECT_GT(s.pairs[0].es_env_steps, 0);
}

// With stop_when_solved, ES alone ends after the iteration whose evaluation solves the target (finished, ≥ 230), as
// the direct path does; without it, only its iteration limit ends it. The finished state is a consistent one.
TEST(EsAlone, StopWhenSolvedEndsTheRunAtTheFirstSolvingEvaluation) {
  for (const bool stop : {true, false}) {
    pb::RunConfig c = tiny_config();
    c.set_mode(pb::RunConfig::ES_ALONE);
    c.set_iterations(6);
    *c.mutable_es_alone()->mutable_target() = to_proto(rough(2.5, 77));
    c.mutable_es_alone()->set_stop_when_solved(stop);
    RunState s = initial_state(run_settings(c));
    int evaluations = 0;  // the third evaluation solves it; 250 without finishing does not
    ScriptedEvaluator ev([&](int, size_t, const RolloutTask& t) {
      if (t.perturbation) return scored(0);
      evaluations += 1;
      return evaluations == 3 ? scored(240, true) : scored(250, false);
    });
    IterationReport last;
    while (!run_complete(s)) last = run_iteration(s, ev);
    EXPECT_EQ(s.finished, stop);
    EXPECT_EQ(s.next_iteration, stop ? 3 : 6) << stop;
    if (stop) {
      EXPECT_EQ(events_named(last, "run_finished").at(0)["reason"], "target solved");
    }
    EXPECT_EQ(check_state_consistency(s), std::nullopt) << stop;
  }
}

// A run with an environment-step budget is complete after the iteration that reaches it, in any mode.
TEST(EnvStepBudget, TheRunEndsAfterTheIterationThatReachesIt) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::ES_ALONE);
  *c.mutable_es_alone()->mutable_target() = to_proto(rough(2.5, 77));
  c.set_env_step_budget(25);  // the scripted rollouts take 10 steps: five an iteration (4 perturbed, 1 evaluation)
  RunState s = initial_state(run_settings(c));
  ScriptedEvaluator ev([](int, size_t, const RolloutTask&) { return scored(1); });
  while (!run_complete(s)) run_iteration(s, ev);
  EXPECT_EQ(s.next_iteration, 1) << "the first iteration's 50 steps reach the budget of 25";
  EXPECT_EQ(s.counters.env_steps, 50);
  c.set_env_step_budget(0);
  RunState unlimited = initial_state(run_settings(c));
  unlimited.counters.env_steps = 1'000'000'000;
  EXPECT_FALSE(run_complete(unlimited)) << "0 is no budget";
}

// ES alone with domain randomisation: the pair keeps its target as its name, and every rollout runs on a course
// drawn at the level.
TEST(EsAlone, DomainRandomisationRunsEveryRolloutOnACourseOfTheLevel) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::ES_ALONE);
  *c.mutable_es_alone()->mutable_target() = to_proto(rough(2.5, 77));
  c.mutable_es_alone()->set_random_courses(pb::EsAloneConfig::CHALLENGING_COURSES);
  RunState s = initial_state(run_settings(c));
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) {
    EXPECT_EQ(difficulty(t.env.encoding), Difficulty::kChallenging);
    return scored(1);
  });
  for (int i = 0; i < 2; ++i) run_iteration(s, ev);
  EXPECT_EQ(s.pairs[0].env.encoding.roughness, 2.5);
  EXPECT_EQ(s.pairs[0].es_steps, 2);
}

TEST(PoetWithoutTransfer, ChildrenStartFromTheirParentAndNoTransferRuns) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::POET_WITHOUT_TRANSFER);
  c.mutable_poet()->set_transfer_interval(1);
  c.mutable_poet()->set_max_admitted(1);
  RunState s = state_at(c, 4, 250);
  add_pair(s, rough(3.0), 0);
  const std::vector<double> parent_theta = s.pairs[0].theta;
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 100); });
  run_iteration(s, ev);
  ASSERT_EQ(ev.batches.size(), 3u);  // MC evaluations, the ES steps, their evaluations: no admission or transfer
  ASSERT_EQ(s.pairs.size(), 3u);
  const Pair& child = s.pairs[2];
  EXPECT_EQ(child.initial_source_pair, 0);
  EXPECT_FALSE(child.initial_by_proposal);
  EXPECT_EQ(child.admission_score, 100);
  EXPECT_EQ(s.counters.transfer_attempts, 0);
}

TEST(PoetWithoutTransfer, CanKeepTheAdmissionSelection) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::POET_WITHOUT_TRANSFER);
  c.mutable_poet()->set_max_admitted(1);
  c.mutable_poet()->set_keep_admission_selection(true);
  RunState s = state_at(c, 4, 250);
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 100); });
  run_iteration(s, ev);
  EXPECT_EQ(ev.batches.size(), 6u);  // with the admission walk's three batches
}

EnvEncoding curriculum_target() {
  EnvEncoding t = named_course("flat").value();
  t.roughness = 1.5;
  t.pit_gap = Interval{0.8, 2.0};
  t.stump_width = Interval{1.0, 2.0};
  t.stump_height = Interval{0.4, 1.0};
  t.stump_float = Interval{0.0, 1.0};
  return t;
}

bool within(const EnvEncoding& e, const EnvEncoding& target) {
  auto le = [](const std::optional<Interval>& a, const std::optional<Interval>& b) {
    return !a || (b && a->lo <= b->lo + 1e-9 && a->hi <= b->hi + 1e-9);
  };
  return e.roughness <= target.roughness + 1e-9 && le(e.pit_gap, target.pit_gap) &&
         le(e.stump_height, target.stump_height);
}

TEST(DirectPath, StepsMoveMonotonicallyTowardTheTargetAndReachIt) {
  const EnvEncoding target = curriculum_target();
  EnvEncoding e = named_course("flat").value();
  RandomStream stream(stream_key(5, "test"));
  int stages = 0;
  while (!e.same_genes(target)) {
    const EnvEncoding next = step_toward(e, target, stream);
    ASSERT_FALSE(validate(next).has_value()) << *validate(next);
    ASSERT_FALSE(next.same_genes(e));
    ASSERT_TRUE(within(next, target));
    EXPECT_GE(next.roughness, e.roughness);
    if (e.pit_gap) {
      EXPECT_GE(next.pit_gap->lo, e.pit_gap->lo);
      EXPECT_GE(next.pit_gap->hi, e.pit_gap->hi);
    }
    e = next;
    ASSERT_LT(++stages, 100);
  }
  EXPECT_GE(stages, 3);  // roughness alone takes three steps of 0.6
  EXPECT_THROW(step_toward(target, target, stream), std::invalid_argument);
}

pb::RunConfig direct_path_config(int64_t budget) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::DIRECT_PATH);
  *c.mutable_direct_path()->mutable_target() = to_proto(EnvDef{curriculum_target(), 4242});
  c.mutable_direct_path()->set_budget_es_steps(budget);
  return c;
}

TEST(DirectPath, AdvancesAtTheThresholdAndStopsWhenTheTargetIsSolved) {
  RunState s = initial_state(run_settings(direct_path_config(1000)));
  EXPECT_EQ(s.pairs[0].env.seed, 4242u);  // every stage uses the target's seed
  ASSERT_EQ(s.stages.size(), 1u);
  // every evaluation scores 240 and finishes: each stage is solved and passed at once
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 240, true); });
  const auto theta_before = s.pairs[0].theta;
  while (!run_complete(s)) run_iteration(s, ev);
  EXPECT_TRUE(s.finished);
  EXPECT_TRUE(s.pairs[0].env.encoding.same_genes(curriculum_target()));
  EXPECT_GE(s.stages.size(), 4u);
  for (const CurriculumStage& st : s.stages) EXPECT_NE(st.solved_iteration, kNone);
  EXPECT_EQ(s.pairs[0].es_steps, static_cast<int64_t>(s.stages.size()));  // one ES step per stage here
  EXPECT_NE(s.pairs[0].theta, theta_before);                              // the agent carries across stages
  EXPECT_GT(s.pairs[0].optimizer.t, 1);                                   // and so does its optimizer
}

TEST(DirectPath, StaysBelowTheThresholdAndStopsWhenTheBudgetIsSpent) {
  RunState s = initial_state(run_settings(direct_path_config(7)));
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 199); });
  IterationReport last;
  while (!run_complete(s)) last = run_iteration(s, ev);
  EXPECT_EQ(s.pairs[0].es_steps, 7);
  EXPECT_EQ(s.stages.size(), 1u);
  EXPECT_EQ(events_named(last, "run_finished").at(0)["reason"], "budget spent");
}

// −‖θ − c‖² of the task's (perturbed) parameters, rebuilt exactly as run_task does.
RolloutResult quadratic(const RolloutTask& t) {
  std::vector<double> theta(*t.theta);
  if (t.perturbation) perturb(*t.theta, t.perturbation->key, t.perturbation->sign, t.perturbation->sigma, theta);
  double f = 0;
  for (double x : theta) f -= (x - 0.2) * (x - 0.2);
  return scored(f);
}

TEST(EsThroughTheEngine, ImprovesASyntheticObjective) {
  pb::RunConfig c = tiny_config();
  c.set_mode(pb::RunConfig::ES_ALONE);
  *c.mutable_es_alone()->mutable_target() = to_proto(rough(0.0));
  c.mutable_es()->set_perturbations(32);
  c.mutable_es()->set_l2_coeff(0);
  RunState s = initial_state(run_settings(c));
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return quadratic(t); });
  run_iteration(s, ev);
  const double start = s.pairs[0].latest_score;
  for (int i = 0; i < 150; ++i) run_iteration(s, ev);
  EXPECT_GT(s.pairs[0].latest_score, 0.3 * start);  // the squared distance to c shrinks by more than 70 %
  EXPECT_EQ(s.pairs[0].best_score, s.pairs[0].latest_score);
}

}  // namespace
}  // namespace poet::testing
