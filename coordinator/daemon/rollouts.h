#pragma once
// Where the rollouts run: threads of this process, or workers over ZeroMQ — the job socket bound (with CURVE when
// asked) before the run is opened, so that a port in use changes no file, and the local workers started once it is.
// Errors are logged.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/plumbing/stop_signals.h"
#include "coordinator/daemon/daemon_options.h"
#include "coordinator/dispatch/local_workers.h"
#include "coordinator/evaluator/remote_evaluator.h"
#include "coordinator/status/status_board.h"
#include "engine/evaluator.h"

namespace poet {

// Where rollouts run: threads of this process, or workers over ZeroMQ (with local ones started here).
struct Rollouts {
  std::unique_ptr<Evaluator> evaluator;
  RemoteEvaluator* remote = nullptr;
  std::vector<std::string> worker_args;  // for local workers
  std::string local_token;
  std::string curve_public_key;  // the job socket's, with CURVE (for the endpoint file)
  std::unique_ptr<LocalWorkers> local_workers;
};

// The evaluator, its socket bound (a port in use or a bad endpoint fails here, before any file is written); local
// workers are started later, by start_local_workers.
std::optional<Rollouts> make_rollouts(const DaemonOptions& options, StopSignals& signals, StatusBoard& board);
// --local-workers: started once the run is open, connected to the bound socket.
bool start_local_workers(const DaemonOptions& options, Rollouts& r);
// The run loop ended: what the workers cost and did is logged. When the run is finished, the board says so (and no
// longer hears from the dispatcher) and the workers are told (they exit); a run finished already when opened then
// waits --linger seconds, telling every worker that connects, or until a stop request.
void end_rollouts(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Rollouts& r, bool finished,
                  bool finished_when_opened);

}  // namespace poet
