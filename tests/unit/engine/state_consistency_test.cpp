// Tests engine/state_consistency.cpp through from_checkpoint: every state the engine writes, over
// random configs of every mode and random lengths, goes through the checkpoint file and back unchanged (a
// property test), and states the engine could not have produced are refused with the rule they break.

#include "engine/state_consistency.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "common/formats/envgen/env_proto.h"
#include "engine_test_support.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "scripted_evaluator.h"
#include "simulation/rng.h"

namespace poet::testing {
namespace {

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// A course with obstacles for the controls' targets, its genes drawn from the stream.
pb::EnvDef random_target(RandomStream& r) {
  EnvDef def{named_course("flat").value(), static_cast<uint32_t>(r.uniform_int(0, 1000))};
  def.encoding.roughness = static_cast<double>(r.uniform_int(0, 40)) / 10;
  if (r.uniform01() < 0.7) def.encoding.pit_gap = Interval{0.2 + r.uniform_int(0, 5) * 0.4, 3.0 + r.uniform_int(0, 5)};
  def.encoding.name = reference_name(def.encoding);
  return to_proto(def);
}

// A random runnable config of a random mode, small enough that a run of a dozen iterations takes milliseconds
// with a scripted evaluator.
pb::RunConfig random_config(RandomStream& r) {
  pb::RunConfig c;
  c.set_mode(static_cast<pb::RunConfig::Mode>(r.uniform_int(0, 4)));
  c.set_seed(r.next_u64());
  c.set_iterations(static_cast<int>(r.uniform_int(1, 13)));
  c.set_init_zero(r.uniform01() < 0.2);
  pb::EsConfig* es = c.mutable_es();
  es->set_perturbations(static_cast<int>(r.uniform_int(1, 4)));
  es->set_init_lr(0.01 + 0.09 * r.uniform01());
  es->set_lr_decay(0.5 + 0.5 * r.uniform01());
  es->set_lr_floor(es->init_lr() * r.uniform01());
  es->set_init_sigma(0.05 + 0.1 * r.uniform01());
  es->set_sigma_decay(0.5 + 0.5 * r.uniform01());
  es->set_sigma_floor(es->init_sigma() * r.uniform01());
  c.mutable_walker()->set_stochastic_envs(r.uniform01() < 0.2);
  c.mutable_walker()->set_eval_episodes(static_cast<int>(r.uniform_int(1, 3)));
  pb::PoetConfig* p = c.mutable_poet();
  p->set_mutation_interval(static_cast<int>(r.uniform_int(1, 4)));
  p->set_transfer_interval(static_cast<int>(r.uniform_int(1, 4)));
  p->set_repro_threshold(-50 + 100 * r.uniform01());
  p->set_mc_low(-100 + 100 * r.uniform01());
  p->set_mc_high(p->mc_low() + 300 * r.uniform01());
  p->set_max_children(static_cast<int>(r.uniform_int(0, 5)));
  p->set_max_admitted(static_cast<int>(r.uniform_int(0, 3)));
  p->set_active_cap(static_cast<int>(r.uniform_int(1, 5)));
  p->set_child_ranking(r.uniform01() < 0.5 ? pb::NOVELTY : pb::LOWEST_SCORE_FIRST);
  p->set_admission_proposal(r.uniform01() < 0.5 ? pb::ADAM_PROPOSAL : pb::SGD_PROPOSAL);
  p->set_transfer_proposal(r.uniform01() < 0.5 ? pb::ADAM_PROPOSAL : pb::SGD_PROPOSAL);
  p->set_solved_score(100 + 150 * r.uniform01());
  if (c.mode() == pb::RunConfig::POET_WITHOUT_TRANSFER) p->set_keep_admission_selection(r.uniform01() < 0.5);
  if (c.mode() == pb::RunConfig::ES_ALONE) *c.mutable_es_alone()->mutable_target() = random_target(r);
  if (c.mode() == pb::RunConfig::DIRECT_PATH) {
    *c.mutable_direct_path()->mutable_target() = random_target(r);
    c.mutable_direct_path()->set_advance_threshold(-50 + 150 * r.uniform01());
    c.mutable_direct_path()->set_budget_es_steps(r.uniform_int(1, 15));
  }
  // drawn last, so the draws above (and the configs they made before this field existed) are unchanged
  // PATA-EC ranks by novelty (the config refuses it beside LOWEST_SCORE_FIRST, which would not read it)
  if (r.uniform01() >= 0.5) {
    p->set_novelty(pb::PATA_EC);
    p->set_child_ranking(pb::NOVELTY);
  }
  return c;
}

// Returns that depend on everything a task holds, spread over [-120, 330): children pass and fail the MC,
// transfers win and lose, courses get solved.
RolloutResult hashed_result(const RolloutTask& task) {
  uint64_t h = mix64(task.env.seed ^ mix64(static_cast<uint64_t>(task.env.encoding.roughness * 1000)));
  h = mix64(h ^ static_cast<uint64_t>((*task.theta)[0] * 1e12));
  if (task.perturbation) h = mix64(h ^ task.perturbation->key ^ static_cast<uint64_t>(task.perturbation->sign + 2));
  const double reward = -120 + 450 * static_cast<double>(h >> 11) / 9007199254740992.0;
  return scored(reward, reward >= 230);
}

// to_checkpoint → the file's bytes → decode → from_checkpoint → to_checkpoint, which must give the same bytes.
void expect_round_trip(const pb::RunConfig& config, const RunState& state, const std::string& where) {
  const std::string bytes = encode_checkpoint_file(to_checkpoint(config, state));
  const Expected<pb::Checkpoint> decoded = decode_checkpoint_file(bytes);
  ASSERT_TRUE(decoded) << where << ": " << decoded.error();
  const Expected<RunState> restored = from_checkpoint(*decoded);
  ASSERT_TRUE(restored) << where << ": the engine wrote a state the reader refuses: " << restored.error();
  EXPECT_EQ(encode_checkpoint_file(to_checkpoint(decoded->config(), *restored)), bytes) << where;
}

TEST(StateConsistency, EveryStateTheEngineWritesReadsBack) {
  RandomStream r(stream_key(2026, "state-consistency"));
  std::map<std::string, int> seen;  // what the runs exercised, so the property is not vacuous
  for (int run = 0; run < 160; ++run) {
    const pb::RunConfig config = random_config(r);
    ASSERT_FALSE(validate(config)) << *validate(config);
    RunState state = initial_state(run_settings(config));
    ScriptedEvaluator evaluator([](int, size_t, const RolloutTask& task) { return hashed_result(task); });
    const std::string name = "run " + std::to_string(run) + " (" + pb::RunConfig::Mode_Name(config.mode()) + ")";
    expect_round_trip(config, state, name + " before iteration 0");
    while (!run_complete(state)) {
      run_iteration(state, evaluator);
      expect_round_trip(config, state, name + " after iteration " + std::to_string(state.next_iteration - 1));
      if (::testing::Test::HasFatalFailure()) return;
    }
    seen[pb::RunConfig::Mode_Name(config.mode())] += 1;
    if (state.pairs.size() > 1) seen["children admitted"] += 1;
    if (state.pairs.size() > 1 && config.poet().novelty() == pb::PATA_EC) seen["PATA-EC children admitted"] += 1;
    if (state.active_indices().size() < state.pairs.size()) seen["pairs retired"] += 1;
    if (state.counters.transfer_successes > 0) seen["transfers accepted"] += 1;
    if (state.finished) seen["control finished"] += 1;
    if (state.stages.size() > 1) seen["curriculum advanced"] += 1;
  }
  for (const char* what :
       {"POET", "POET_WITHOUT_TRANSFER", "ES_ALONE", "DIRECT_PATH", "children admitted", "PATA-EC children admitted",
        "pairs retired", "transfers accepted", "control finished", "curriculum advanced"})
    EXPECT_GE(seen[what], 3) << "too few runs with " << what;
}

// A config and the state a short real run of the engine leaves.
struct EngineRun {
  pb::RunConfig config;
  RunState state;
};

// A run of each kind.
EngineRun engine_run(pb::RunConfig::Mode mode, int iterations) {
  RandomStream r(stream_key(7, "engine-state"));
  pb::RunConfig config = tiny_config();
  config.set_mode(mode);
  config.set_iterations(iterations);
  pb::PoetConfig* p = config.mutable_poet();
  p->set_mutation_interval(1);
  p->set_transfer_interval(1);
  p->set_repro_threshold(-1000);
  p->set_mc_low(-1000);
  p->set_mc_high(1000);
  p->set_max_admitted(1);
  p->set_active_cap(2);
  if (mode == pb::RunConfig::ES_ALONE) *config.mutable_es_alone()->mutable_target() = random_target(r);
  if (mode == pb::RunConfig::DIRECT_PATH) {
    *config.mutable_direct_path()->mutable_target() = random_target(r);
    config.mutable_direct_path()->set_budget_es_steps(100);
  }
  RunState state = initial_state(run_settings(config));
  ScriptedEvaluator evaluator([](int, size_t, const RolloutTask& task) { return hashed_result(task); });
  while (!run_complete(state)) run_iteration(state, evaluator);
  return {config, std::move(state)};
}

// The error from_checkpoint gives for the run's message after `edit`.
template <class Edit>
std::string refusal(const EngineRun& run, Edit edit) {
  pb::Checkpoint message = to_checkpoint(run.config, run.state);
  edit(message);
  const Expected<RunState> restored = from_checkpoint(message);
  return restored ? std::string("accepted") : restored.error();
}

TEST(StateConsistency, RefusesStatesTheEngineCouldNotHaveProduced) {
  const EngineRun poet = engine_run(pb::RunConfig::POET, 4);
  ASSERT_GE(poet.state.pairs.size(), 3u);
  ASSERT_LT(poet.state.active_indices().size(), poet.state.pairs.size());
  const EngineRun direct = engine_run(pb::RunConfig::DIRECT_PATH, 3);
  const EngineRun alone = engine_run(pb::RunConfig::ES_ALONE, 2);
  for (const EngineRun* s : {&poet, &direct, &alone}) ASSERT_EQ(refusal(*s, [](pb::Checkpoint&) {}), "accepted");

  // the reported crash: a DIRECT_PATH state without its curriculum
  EXPECT_TRUE(
      contains(refusal(direct, [](pb::Checkpoint& m) { m.clear_stages(); }), "stages: none in mode DIRECT_PATH"));
  EXPECT_TRUE(contains(refusal(direct, [](pb::Checkpoint& m) { *m.add_pairs() = m.pairs(0); }), "pairs"));
  // ES alone with two pairs: the POET state relabelled
  EXPECT_TRUE(contains(refusal(poet,
                               [&](pb::Checkpoint& m) {
                                 m.mutable_config()->set_mode(pb::RunConfig::ES_ALONE);
                                 *m.mutable_config()->mutable_es_alone()->mutable_target() =
                                     alone.config.es_alone().target();
                               }),
                       "in mode ES_ALONE, which keeps one"));
  EXPECT_TRUE(contains(refusal(alone, [](pb::Checkpoint& m) { m.mutable_pairs(0)->mutable_env()->set_seed(999999); }),
                       "is not es_alone.target"));
  // every pair retired
  EXPECT_TRUE(contains(refusal(poet,
                               [](pb::Checkpoint& m) {
                                 for (auto& p : *m.mutable_pairs())
                                   if (p.retired_iteration() == -1) p.set_retired_iteration(m.next_iteration() - 1);
                               }),
                       "none active"));
  EXPECT_TRUE(contains(refusal(poet, [](pb::Checkpoint& m) { m.mutable_config()->mutable_poet()->set_active_cap(1); }),
                       "more than poet.active_cap"));
  EXPECT_TRUE(contains(refusal(poet, [](pb::Checkpoint& m) { m.set_finished(true); }), "finished: true"));
  EXPECT_TRUE(contains(
      refusal(poet, [&](pb::Checkpoint& m) { *m.add_stages() = to_checkpoint(direct.config, direct.state).stages(0); }),
      "stages: a curriculum"));
  EXPECT_TRUE(contains(refusal(poet,
                               [](pb::Checkpoint& m) {
                                 m.mutable_counters()->set_children_admitted(m.counters().children_admitted() + 1);
                               }),
                       "counters.children_admitted"));
  EXPECT_TRUE(contains(refusal(poet,
                               [](pb::Checkpoint& m) {
                                 m.mutable_counters()->set_transfer_attempts(m.counters().transfer_attempts() + 1);
                               }),
                       "counters.transfer_attempts"));
  EXPECT_TRUE(
      contains(refusal(poet, [](pb::Checkpoint& m) { m.mutable_pairs(1)->set_parent_id(2); }), "pairs[1].parent_id"));
  EXPECT_TRUE(contains(refusal(poet, [](pb::Checkpoint& m) { m.mutable_pairs(0)->mutable_optimizer()->set_lr(1); }),
                       "pairs[0].optimizer.lr"));
  EXPECT_TRUE(
      contains(refusal(poet, [](pb::Checkpoint& m) { m.mutable_pairs(0)->set_es_steps(m.next_iteration() + 1); }),
               "pairs[0].es_steps"));
  // transfer records in a mode without transfer
  EXPECT_TRUE(contains(
      refusal(poet, [](pb::Checkpoint& m) { m.mutable_config()->set_mode(pb::RunConfig::POET_WITHOUT_TRANSFER); }),
      "mode POET_WITHOUT_TRANSFER"));
}

}  // namespace
}  // namespace poet::testing
