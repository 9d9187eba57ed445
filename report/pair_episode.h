#pragma once
// A pair's episode as the pictures and the dashboard's replay show it.

#include "common/plumbing/expected.h"
#include "run_directory/reading/run_snapshot.h"
#include "simulation/rollout.h"

namespace poet {

// The episode of a pair's current θ on its own course with the run's walker settings, trajectory recorded; an
// error for an unknown pair.
Expected<RolloutResult> pair_episode(const RunSnapshot& run, int pair);

}  // namespace poet
