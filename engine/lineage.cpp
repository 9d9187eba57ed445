#include "engine/lineage.h"

#include <algorithm>
#include <vector>

namespace poet {
namespace {

// The last iteration in which the pair took an ES step, given the run's progress.
int last_step(const RunState& state, const Pair& pair) {
  const int end = pair.active() ? state.next_iteration : pair.retired_iteration;  // exclusive
  return end - 1;
}

}  // namespace

std::map<int, int> lineage_horizons(const RunState& state, int pair_id) {
  std::map<int, int> horizon;
  const Pair* target = state.find(pair_id);
  if (!target) return horizon;

  std::vector<std::pair<int, int>> work = {
      {pair_id, target->solved() ? target->first_solved_iteration : last_step(state, *target)}};
  while (!work.empty()) {
    const auto [id, until] = work.back();
    work.pop_back();
    auto it = horizon.find(id);
    if (it != horizon.end() && it->second >= until) continue;  // already counted at least this far
    horizon[id] = until;
    const Pair* pair = state.find(id);
    if (!pair) continue;
    for (int source : {pair->parent_id, pair->initial_source_pair})
      if (source != kNone) work.push_back({source, pair->created_iteration - 1});
    for (const TransferRecord& t : pair->transfers)
      if (t.iteration <= until) work.push_back({t.source_pair, t.iteration});
  }
  return horizon;
}

int64_t lineage_es_steps(const RunState& state, int pair_id) {
  int64_t steps = 0;
  for (const auto& [id, until] : lineage_horizons(state, pair_id)) {
    const Pair* pair = state.find(id);
    if (!pair) continue;
    const int last = std::min(until, last_step(state, *pair));
    steps += std::max(0, last - pair->created_iteration + 1);
  }
  return steps;
}

std::optional<int64_t> lineage_env_steps(const RunState& state, int pair_id, const PairEnvStepsAt& env_steps_after) {
  int64_t steps = 0;
  for (const auto& [id, until] : lineage_horizons(state, pair_id)) {
    const Pair* pair = state.find(id);
    if (!pair) continue;
    const int last = std::min(until, last_step(state, *pair));
    if (last < pair->created_iteration) continue;  // no ES step of its counts
    const std::optional<int64_t> at = env_steps_after(id, last);
    if (!at) return std::nullopt;
    steps += *at;
  }
  return steps;
}

}  // namespace poet
