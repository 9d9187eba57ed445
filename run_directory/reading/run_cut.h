#pragma once
// A run as it stood at the end of an earlier iteration, for comparing runs at equal budgets (POET against POET
// without transfer, two seeds) from the files of runs that went further. Only what the metrics read is cut back:
// pairs created later are dropped, solves, retirements and transfers after it undone, the counters, scores and ES
// steps taken from the logs at that iteration, the logs' lines after it left out. The pairs' θs and optimizers
// stay as they are now (no metric reads them), so a cut run is for reports, never for resuming.

#include <cstdint>
#include <optional>

#include "run_directory/reading/run_snapshot.h"

namespace poet {

// The run after iteration `last` (0 ≤ last). A last at or beyond the run's last iteration leaves it as it is.
RunSnapshot cut_run(RunSnapshot run, int last);

// The last iteration by whose ES steps and evaluations the run had taken at most env_steps environment steps
// (pair_stats.csv's run_env_steps, as poet-report counts its milestones); nothing when iteration 0 already took
// more, or the run's logs do not record them.
std::optional<int> last_iteration_within(const RunSnapshot& run, int64_t env_steps);

}  // namespace poet
