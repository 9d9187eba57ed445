#pragma once
// The worker's socket loop: a ZeroMQ DEALER connected to the coordinator's ROUTER, one serialized WorkerMessage
// per frame out, one CoordinatorMessage per frame in. It only moves bytes and jobs: every decision is the
// WorkerSession's. It polls the socket and a wake-up pipe with a short timeout (never blocking on a job, which
// runs in the JobExecutor its caller gives it: a JobRunner's thread in poet-worker), so heartbeats go out on time
// while a job runs. It also watches the socket's connections and handshakes, so a worker the coordinator refuses
// at the security layer (a CURVE key it does not accept, CURVE on one side only), or whose peer speaks another
// protocol, says so (handshake_failure.h) and tries again on a fresh socket; and while no Welcome comes it says now
// and then that it is still trying, and where.

#include <atomic>
#include <optional>
#include <string>

#include "common/plumbing/wake_pipe.h"
#include "worker/job_executor.h"
#include "worker/worker_session.h"

namespace poet::worker {

// CURVE keys of a worker (common/plumbing/curve_keys.h): its own pair and the coordinator's public key, all Z85.
struct CurveClient {
  std::string server_public_key;
  std::string public_key;
  std::string secret_key;
};

struct LoopSettings {
  std::string endpoint;  // tcp://HOST:PORT of the coordinator's ROUTER
  // A coordinator's endpoint file (common/plumbing/endpoint_file.h), read instead of `endpoint` (and of curve's
  // server key, when it has one) each time a fresh socket is opened: a coordinator that moves is followed.
  std::string endpoint_file;
  SessionSettings session;
  std::optional<CurveClient> curve;  // none: no authentication
};

// Runs the worker until the session ends (Refused: 2, Shutdown: 0) or `stop` is set (Goodbye, 0), and returns
// the process exit code. The jobs the session accepts go to `jobs`, which must call wake.notify() when an outcome
// is ready (JobRunner's on_finished); whoever sets `stop` must then call wake.notify() too.
int run_worker(const LoopSettings& settings, JobExecutor& jobs, WakePipe& wake, const std::atomic<bool>& stop);

}  // namespace poet::worker
