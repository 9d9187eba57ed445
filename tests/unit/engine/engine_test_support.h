#pragma once
// Small builders shared by the engine's logic tests: a tiny config and hand-made pairs.

#include <vector>

#include "coordinator/evaluator/local_evaluator.h"
#include "engine/engine.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/event_json.h"
#include "run_directory/files/run_directory.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"

namespace poet::testing {

// POET with 2 perturbations per ES step, reproduction every 4 iterations, transfer only at 0 (never with one
// pair), MC 50..300, threshold 200, 6 children, no admissions: each test turns on what it checks.
inline pb::RunConfig tiny_config() {
  pb::RunConfig c;
  c.set_seed(3);
  c.set_iterations(100);
  c.mutable_es()->set_perturbations(2);
  pb::PoetConfig* p = c.mutable_poet();
  p->set_mutation_interval(4);
  p->set_transfer_interval(1000);
  p->set_mc_low(50);
  p->set_mc_high(300);
  p->set_repro_threshold(200);
  p->set_max_children(6);
  p->set_max_admitted(0);
  p->set_active_cap(10);
  return c;
}

// Real rollouts, short: 3 perturbations, 100-step episodes, 7 iterations; reproduction and transfer every other
// iteration with criteria every child passes, at most 3 active pairs, so every part of the loop runs.
inline pb::RunConfig small_real_run() {
  pb::RunConfig c;
  c.set_seed(5);
  c.set_iterations(7);
  c.mutable_es()->set_perturbations(3);
  c.mutable_walker()->set_max_steps(100);
  pb::PoetConfig* p = c.mutable_poet();
  p->set_mutation_interval(2);
  p->set_transfer_interval(2);
  p->set_repro_threshold(-1000);
  p->set_mc_low(-1000);
  p->set_mc_high(1000);
  p->set_max_children(3);
  p->set_max_admitted(1);
  p->set_active_cap(3);
  return c;
}

// small_real_run on CPPN terrain, children ranked by their minimal-criterion score (the encoding distance sees
// nothing in a CPPN course, and PATA-EC has runs of its own).
inline pb::RunConfig small_cppn_run() {
  pb::RunConfig c = small_real_run();
  c.mutable_poet()->set_environments(pb::CPPN_TERRAIN);
  c.mutable_poet()->set_child_ranking(pb::LOWEST_SCORE_FIRST);
  return c;
}

// small_real_run with Enhanced POET's PATA-EC novelty: each reproduction evaluates every θ on every archived
// environment and passing child, and from the second on two or more agents rank them.
inline pb::RunConfig small_pata_ec_run() {
  pb::RunConfig c = small_real_run();
  c.mutable_poet()->set_novelty(pb::PATA_EC);
  return c;
}

inline EnvDef rough(double roughness, uint32_t seed = 11) {
  EnvDef def{named_course("flat").value(), seed};
  def.encoding.roughness = roughness;
  def.encoding.name = "r" + std::to_string(roughness);
  return def;
}

// Appends a pair on env with a recognisable constant θ and the given latest score.
inline Pair& add_pair(RunState& state, const EnvDef& env, double latest_score) {
  Pair p;
  p.id = state.next_pair_id++;
  p.env = env;
  p.theta.assign(kParamCount, 0.01 * (p.id + 1));
  p.best_theta = p.theta;
  p.optimizer = fresh_optimizer(state.settings.es, kParamCount);
  p.latest_score = latest_score;
  p.best_score = latest_score;
  p.best_iteration = 0;
  state.pairs.push_back(std::move(p));
  return state.pairs.back();
}

// A state whose first pair has the given latest score, about to run iteration t.
inline RunState state_at(const pb::RunConfig& config, int t, double first_score) {
  RunState s = initial_state(run_settings(config));
  s.pairs[0].latest_score = first_score;
  s.next_iteration = t;
  return s;
}

inline std::vector<nlohmann::ordered_json> events_named(const IterationReport& r, const std::string& name) {
  std::vector<nlohmann::ordered_json> out;
  for (const auto& e : events_json(r))
    if (e["event"] == name) out.push_back(e);
  return out;
}

// Runs config in dir to the end of iteration until − 1, as the coordinator does (a checkpoint after each
// iteration): from its start, or from the checkpoint dir holds. Returns an error message, or nothing.
inline std::optional<std::string> run_in_directory(const std::filesystem::path& dir, const pb::RunConfig& config,
                                                   int until) {
  std::optional<RunDirectory> run;
  RunState state;
  if (std::filesystem::exists(dir / kCheckpointFile)) {
    Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(dir);
    if (!resumed) return resumed.error();
    run.emplace(std::move(resumed->first));
    state = std::move(resumed->second);
  } else {
    Expected<RunDirectory> created = RunDirectory::create(dir, config);
    if (!created) return created.error();
    run.emplace(std::move(*created));
    state = initial_state(run_settings(config));
    if (auto error = run->save(state)) return error;
  }
  LocalEvaluator evaluator(2);
  while (state.next_iteration < until && !run_complete(state)) {
    run->append(run_iteration(state, evaluator));
    if (auto error = run->save(state)) return error;
  }
  return std::nullopt;
}

}  // namespace poet::testing
