// poet-lineage: a pair's lineage in a run directory (parent, first θ, accepted transfers, solve) and the
// direct-path control's budget for its environment; with --direct-path-config, a runnable config for that
// control (the run's settings, mode DIRECT_PATH, the pair's environment as the target, the budget); with
// --es-alone-config, the ES-alone control with the same budget in ES steps (stopping, as the direct path does, once
// it solves the target). It prints the environment steps of that budget too, from pair_stats.csv (runs of earlier
// builds did not record a pair's).
//   poet-lineage --run-dir DIR --pair ID [--direct-path-config | --es-alone-config [--seed N]]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <climits>
#include <cstdio>
#include <iostream>

#include "common/formats/envgen/env_proto.h"
#include "common/program/tool_flags.h"
#include "engine/lineage.h"
#include "run_directory/config/run_config.h"
#include "run_directory/reading/run_snapshot.h"

int run_tool(int argc, char** argv) {
  using namespace poet;
  CLI::App app{"A pair's lineage and the direct-path budget of its environment"};
  std::string run_dir;
  int pair_id = 0;
  bool emit_config = false, emit_es_alone = false;
  app.add_option("--run-dir", run_dir, "Run directory")->required();
  app.add_option("--pair", pair_id, "Pair id")->required();
  auto* direct_flag =
      app.add_flag("--direct-path-config", emit_config, "Print a DIRECT_PATH run config for this pair's environment");
  app.add_flag("--es-alone-config", emit_es_alone,
               "Print an ES_ALONE run config for this pair's environment with the same budget in ES steps")
      ->excludes(direct_flag);
  uint64_t seed = 0;
  auto* seed_option = app.add_option("--seed", seed,
                                     "The control's seed (its ES noise and, for the direct path, its stage draws; "
                                     "default: the run's), for independent runs of one control");
  add_fingerprint_flag(app);
  if (auto code = parse_command_line(app, argc, argv)) return *code;

  // read without touching the run's files (resume would truncate its logs, and take the lock)
  const Expected<RunSnapshot> run = read_run_snapshot(run_dir);
  if (!run) {
    std::cerr << run.error() << "\n";
    return 2;
  }
  const RunState* state = &run->state;
  const Pair* pair = state->find(pair_id);
  if (!pair) {
    std::cerr << "no pair " << pair_id << " in " << run_dir << "\n";
    return 2;
  }
  const int64_t budget = lineage_es_steps(*state, pair_id);

  if (emit_config && pair->env.encoding.is_cppn()) {
    std::cerr << "pair " << pair_id << "'s environment is a CPPN course, which has no direct path from flat (the "
              << "curriculum steps obstacle genes); --es-alone-config gives the ES-alone control on it\n";
    return 2;
  }
  if (emit_config || emit_es_alone) {
    // the run's settings (ES, walker, seed) with the pair's environment as the target
    pb::RunConfig config = run->config;
    if (seed_option->count() > 0) config.set_seed(seed);
    config.clear_es_alone();
    config.clear_direct_path();
    config.mutable_poet()->clear_keep_admission_selection();
    config.mutable_poet()->clear_transfer_test();  // a control has no transfers; nothing to keep scores for
    config.mutable_poet()->clear_environments();   // nor reproduction: the kind of environment and the novelty
    config.mutable_poet()->clear_novelty();        // measure do not apply
    if (emit_config) {
      config.set_mode(pb::RunConfig::DIRECT_PATH);
      pb::DirectPathConfig* direct = config.mutable_direct_path();
      *direct->mutable_target() = to_proto(pair->env);
      direct->set_budget_es_steps(budget);
    } else {
      config.set_mode(pb::RunConfig::ES_ALONE);
      *config.mutable_es_alone()->mutable_target() = to_proto(pair->env);
      config.mutable_es_alone()->set_stop_when_solved(true);  // like the direct path: the result is the same
      config.set_iterations(static_cast<int>(std::min<int64_t>(budget, INT32_MAX)));  // one ES step an iteration
    }
    std::cout << run_config_text(config);
    return 0;
  }
  std::printf("pair %d: %s seed %u, created at iteration %d\n", pair->id, pair->env.encoding.name.c_str(),
              pair->env.seed, pair->created_iteration);
  std::printf("  parent %d; first θ from pair %d (%s)\n", pair->parent_id, pair->initial_source_pair,
              pair->initial_by_proposal ? "proposal" : "direct");
  for (const TransferRecord& t : pair->transfers)
    std::printf("  transfer at %d from pair %d (%s), score %.2f\n", t.iteration, t.source_pair,
                t.proposal ? "proposal" : "direct", t.score);
  if (pair->solved())
    std::printf("  solved at iteration %d\n", pair->first_solved_iteration);
  else
    std::printf("  not solved (best %.2f)\n", pair->best_score);
  std::printf("contributors (pair: last counted iteration):");
  for (const auto& [id, until] : lineage_horizons(*state, pair_id)) std::printf(" %d:%d", id, until);
  std::printf("\ndirect-path budget: %lld ES steps\n", static_cast<long long>(budget));
  const std::optional<int64_t> env_steps = lineage_env_steps(*state, pair_id, pair_env_steps_at(run->stats));
  if (env_steps)
    std::printf("environment steps of those ES steps: %lld\n", static_cast<long long>(*env_steps));
  else
    std::printf("environment steps of those ES steps: not recorded (a run of a build before pair_env_steps)\n");
  return 0;
}

int main(int argc, char** argv) { return poet::output_checked("poet-lineage", run_tool(argc, argv)); }
