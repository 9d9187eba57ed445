#pragma once
// The run loop once the run is open: iterations, checkpoints and the wall times, going back to a checkpoint when
// a worker was found wrong (with verification), and the end of the run — the last iterations saved, the summaries
// logged, the workers told when the run is finished. The process's exit code.

#include <chrono>
#include <utility>

#include "common/stop_signals.h"
#include "coordinator/daemon/daemon_options.h"
#include "coordinator/daemon/rollouts.h"
#include "coordinator/status/status_board.h"
#include "engine/run_state.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/wall_times.h"

namespace poet {

int run_loop(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Rollouts& rollouts,
             std::pair<RunDirectory, RunState> opened, WallTimes wall_times,
             std::chrono::steady_clock::time_point started);

}  // namespace poet
