#pragma once
// Reading a run's lineage records (spec §3): the ES steps POET spent on an environment's line of ancestors, which
// is the direct-path control's budget for that environment.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>

#include "engine/run_state.h"

namespace poet {

// For each pair that contributed to pair_id's agent, the last iteration whose ES step counts: the pair itself up
// to its first solve (or its last step); its parent and the source of its first θ up to the iteration before
// its creation (reproduction runs before the ES steps); each accepted transfer's source up to the transfer's
// iteration (transfer runs after them) — and so on, recursively, for every contributor. Empty for an unknown id.
std::map<int, int> lineage_horizons(const RunState& state, int pair_id);

// The ES steps of those contributors up to their horizons: every active pair takes one ES step per iteration
// from its creation until it retires. The direct-path budget for pair_id.
int64_t lineage_es_steps(const RunState& state, int pair_id);

// The environment steps of the same ES steps (their perturbed rollouts and evaluations): for each contributor,
// env_steps_after(pair, iteration), the pair's es_env_steps after its ES step of that iteration (pair_stats.csv's
// pair_env_steps), at its horizon. Nothing when one of them is not known (a run from before they were counted).
using PairEnvStepsAt = std::function<std::optional<int64_t>(int pair, int iteration)>;
std::optional<int64_t> lineage_env_steps(const RunState& state, int pair_id, const PairEnvStepsAt& env_steps_after);

}  // namespace poet
