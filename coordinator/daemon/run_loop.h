#pragma once
// The run loop once the run is open: iterations, checkpoints and the wall times, going back to a checkpoint when
// the evaluator withdraws results it returned (engine/evaluator.h: a worker found wrong, with verification), and
// the end of the run — the last iterations saved, the summaries logged. Telling the workers is their owner's
// (rollouts.h: end_rollouts).

#include <chrono>
#include <utility>

#include "common/plumbing/stop_signals.h"
#include "coordinator/daemon/daemon_options.h"
#include "coordinator/status/status_board.h"
#include "engine/evaluator.h"
#include "engine/run_state.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/wall_times.h"

namespace poet {

// How the loop ended.
struct RunEnd {
  int exit_code = 0;                  // the process's
  bool finished = false;              // the run is complete: its workers may be told so
  bool finished_when_opened = false;  // it was complete already: the process only lingers (--linger) for them
};

// Runs the iterations on `rollouts` (the evaluator, which the loop puts its score cache in front of).
RunEnd run_loop(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Evaluator& rollouts,
                std::pair<RunDirectory, RunState> opened, WallTimes wall_times,
                std::chrono::steady_clock::time_point started);

}  // namespace poet
