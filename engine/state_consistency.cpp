#include "engine/state_consistency.h"

#include <cstdint>
#include <string>

#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

using Error = std::optional<std::string>;

std::string str(int64_t value) { return std::to_string(value); }
std::string pair_field(size_t i) { return "pairs[" + std::to_string(i) + "]"; }

bool same_env(const EnvDef& a, const EnvDef& b) { return a.seed == b.seed && a.encoding.same_genes(b.encoding); }

// Rules every mode keeps, pair by pair.
Error check_pair(const RunState& state, size_t i, const EsSettings& es) {
  const Pair& p = state.pairs[i];
  const std::string field = pair_field(i);
  const auto before_creation = [&](int iteration) { return iteration != kNone && iteration < p.created_iteration; };
  if (before_creation(p.retired_iteration))
    return field + ".retired_iteration: " + str(p.retired_iteration) + " precedes its creation at iteration " +
           str(p.created_iteration);
  if (before_creation(p.first_solved_iteration))
    return field + ".first_solved_iteration: " + str(p.first_solved_iteration) + " precedes its creation at " +
           str(p.created_iteration);
  if (before_creation(p.best_iteration))
    return field + ".best_iteration: " + str(p.best_iteration) + " precedes its creation at " +
           str(p.created_iteration);
  // one ES step per iteration, and Adam's count restarts on a reset, never runs ahead of the steps taken
  if (p.es_steps > state.next_iteration)
    return field + ".es_steps: " + str(p.es_steps) + " exceeds the " + str(state.next_iteration) + " iterations run";
  if (p.optimizer.t > p.es_steps)
    return field + ".optimizer.t: " + str(p.optimizer.t) + " exceeds its ES steps " + str(p.es_steps);
  // lr and σ start at their initial values and only decay toward their floors
  if (p.optimizer.lr > es.init_lr || p.optimizer.lr < es.lr_floor)
    return field + ".optimizer.lr: " + std::to_string(p.optimizer.lr) + " outside [es.lr_floor, es.init_lr]";
  if (p.optimizer.sigma > es.init_sigma || p.optimizer.sigma < es.sigma_floor)
    return field + ".optimizer.sigma: " + std::to_string(p.optimizer.sigma) +
           " outside [es.sigma_floor, es.init_sigma]";
  if (!p.recent_scores.empty() && state.settings.poet.transfer_test != TransferTest::kThreshold)
    return field + ".recent_scores: kept only under poet.transfer_test THRESHOLD_TRANSFER_TEST";
  for (size_t k = 0; k < p.transfers.size(); ++k) {
    const TransferRecord& r = p.transfers[k];
    const std::string path = field + ".transfers[" + std::to_string(k) + "]";
    if (r.source_pair == p.id) return path + ".source_pair: the pair itself (" + str(p.id) + ")";
    if (r.iteration < p.created_iteration || (k > 0 && r.iteration <= p.transfers[k - 1].iteration))
      return path + ".iteration: " + str(r.iteration) + " out of order (transfers follow creation, one a round)";
  }
  return std::nullopt;
}

// ES alone and the direct path: one pair, never reproduced, never a transfer.
Error check_single_pair(const RunState& state) {
  const std::string mode(mode_name(state.settings.mode));
  if (state.pairs.size() != 1)
    return "pairs: " + str(static_cast<int64_t>(state.pairs.size())) + " in mode " + mode + ", which keeps one";
  const Pair& p = state.pairs.front();
  if (p.id != 0 || state.next_pair_id != 1) return "pairs[0].id: mode " + mode + " has only pair 0";
  if (!p.active()) return "pairs[0].retired_iteration: " + str(p.retired_iteration) + " in mode " + mode;
  if (p.parent_id != kNone || p.initial_source_pair != kNone) return "pairs[0].parent_id: set in mode " + mode;
  if (!p.transfers.empty() || p.transfer_attempts != 0 || state.counters.transfer_attempts != 0)
    return "pairs[0].transfers: transfers in mode " + mode;
  if (state.counters.children_tried != 0) return "counters.children_tried: children in mode " + mode;
  return std::nullopt;
}

Error check_es_alone(const RunState& state) {
  if (Error error = check_single_pair(state)) return error;
  if (!state.stages.empty()) return "stages: a curriculum in mode ES_ALONE";
  if (state.finished && !state.settings.stop_when_solved)
    return "finished: true in mode ES_ALONE without stop_when_solved, which stops at its iteration limit only";
  const EnvDef target = state.settings.target.value();
  if (!same_env(state.pairs.front().env, target))
    return "pairs[0].env: " + state.pairs.front().env.encoding.name + " is not es_alone.target " + target.encoding.name;
  return std::nullopt;
}

Error check_direct_path(const RunState& state) {
  if (Error error = check_single_pair(state)) return error;
  if (state.stages.empty()) return "stages: none in mode DIRECT_PATH (the curriculum starts with the flat course)";
  const EnvDef target = state.settings.target.value();
  const EnvDef first{named_course("flat").value(), target.seed};
  if (!same_env(state.stages.front().env, first) || state.stages.front().started_iteration != 0)
    return "stages[0]: must be the flat course with the target's seed, started at iteration 0";
  for (size_t s = 0; s < state.stages.size(); ++s) {
    const CurriculumStage& stage = state.stages[s];
    const std::string field = "stages[" + std::to_string(s) + "]";
    if (stage.env.seed != target.seed)
      return field + ".env.seed: " + str(stage.env.seed) + ", the target's is " + str(target.seed);
    if (s > 0 && stage.started_iteration <= state.stages[s - 1].started_iteration)
      return field + ".started_iteration: " + str(stage.started_iteration) + " does not follow the previous stage's";
    if (stage.started_iteration > state.next_iteration)
      return field + ".started_iteration: " + str(stage.started_iteration) + " is after the next iteration " +
             str(state.next_iteration);
    if (stage.solved_iteration != kNone && stage.solved_iteration < stage.started_iteration)
      return field + ".solved_iteration: " + str(stage.solved_iteration) + " precedes the stage's start";
  }
  if (!same_env(state.stages.back().env, state.pairs.front().env))
    return "pairs[0].env: " + state.pairs.front().env.encoding.name + " is not the last stage's " +
           state.stages.back().env.encoding.name;
  return std::nullopt;
}

Error check_poet(const RunState& state) {
  const PoetSettings& poet = state.settings.poet;
  const bool with_transfer = state.settings.mode == RunMode::kPoet;
  if (!state.stages.empty()) return "stages: a curriculum in a POET mode";
  if (state.finished) return "finished: true in a POET mode, which stops at its iteration limit only";

  const Pair& first = state.pairs.front();
  if (first.id != 0 || first.parent_id != kNone || first.created_iteration != 0)
    return "pairs[0]: the first pair is id 0, created at iteration 0 without a parent";
  int64_t active = 0;
  int64_t attempts = 0;
  int64_t successes = 0;
  for (size_t i = 0; i < state.pairs.size(); ++i) {
    const Pair& p = state.pairs[i];
    const std::string field = pair_field(i);
    active += p.active() ? 1 : 0;
    attempts += p.transfer_attempts;
    successes += static_cast<int64_t>(p.transfers.size());
    if (!with_transfer && (p.transfer_attempts != 0 || !p.transfers.empty()))
      return field + ".transfers: transfers in mode POET_WITHOUT_TRANSFER";
    for (const TransferRecord& r : p.transfers)
      if (r.iteration % poet.transfer_interval != 0)
        return field + ".transfers: a transfer at iteration " + str(r.iteration) +
               ", not a multiple of poet.transfer_interval " + str(poet.transfer_interval);
    // pairs retire at reproductions (iterations t > 0 with t % mutation_interval == 0)
    if (!p.active() && (p.retired_iteration == 0 || p.retired_iteration % poet.mutation_interval != 0))
      return field + ".retired_iteration: " + str(p.retired_iteration) + " is not a reproduction iteration";
    if (i == 0) continue;
    // children are admitted at reproductions, from a parent already in the archive
    if (p.created_iteration == 0 || p.created_iteration % poet.mutation_interval != 0)
      return field + ".created_iteration: " + str(p.created_iteration) + " is not a reproduction iteration";
    const Pair* parent = p.parent_id == kNone ? nullptr : state.find(p.parent_id);
    if (!parent || parent->id >= p.id || parent->created_iteration > p.created_iteration)
      return field + ".parent_id: " + str(p.parent_id) + " is not an earlier pair";
  }
  if (active < 1) return "pairs: none active (a POET run always keeps at least one)";
  if (active > poet.active_cap)
    return "pairs: " + str(active) + " active, more than poet.active_cap " + str(poet.active_cap);

  const RunCounters& c = state.counters;
  if (c.children_admitted != static_cast<int64_t>(state.pairs.size()) - 1)
    return "counters.children_admitted: " + str(c.children_admitted) + ", but the archive holds " +
           str(static_cast<int64_t>(state.pairs.size()) - 1) + " children";
  if (c.children_passed_mc < c.children_admitted || c.children_tried < c.children_passed_mc)
    return "counters.children_passed_mc: " + str(c.children_passed_mc) + " outside [children_admitted " +
           str(c.children_admitted) + ", children_tried " + str(c.children_tried) + "]";
  if (c.transfer_attempts != attempts)
    return "counters.transfer_attempts: " + str(c.transfer_attempts) + ", the pairs count " + str(attempts);
  if (c.transfer_successes != successes)
    return "counters.transfer_successes: " + str(c.transfer_successes) + ", the pairs record " + str(successes);
  return std::nullopt;
}

}  // namespace

std::optional<std::string> check_state_consistency(const RunState& state) {
  for (size_t i = 0; i < state.pairs.size(); ++i)
    if (Error error = check_pair(state, i, state.settings.es)) return error;
  switch (state.settings.mode) {
    case RunMode::kEsAlone:
      return check_es_alone(state);
    case RunMode::kDirectPath:
      return check_direct_path(state);
    default:
      return check_poet(state);
  }
}

}  // namespace poet
