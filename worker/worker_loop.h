#pragma once
// The worker's socket loop: a ZeroMQ DEALER connected to the coordinator's ROUTER, one serialized WorkerMessage
// per frame out, one CoordinatorMessage per frame in. It only moves bytes and jobs: every decision is the
// WorkerSession's. It polls the socket and a wake-up pipe with a short timeout (never blocking on a job, which
// runs on the JobRunner's thread), so heartbeats go out on time while a job runs.

#include <atomic>
#include <string>

#include "worker_session.h"

namespace poet::worker {

// A self-pipe that wakes the loop's poll: written by the job runner (an outcome is ready) and by the signal
// thread (stop). notify() is safe from any thread and never blocks.
class WakePipe {
 public:
  WakePipe();  // throws std::system_error when no pipe can be made
  ~WakePipe();
  WakePipe(const WakePipe&) = delete;
  WakePipe& operator=(const WakePipe&) = delete;

  void notify();
  void drain();  // the loop's side: empties the pipe
  int read_fd() const { return fds_[0]; }

 private:
  int fds_[2] = {-1, -1};
};

struct LoopSettings {
  std::string endpoint;  // tcp://HOST:PORT of the coordinator's ROUTER
  int threads = 1;       // episodes the job runner runs at once
  SessionSettings session;
};

// Runs the worker until the session ends (Refused: 2, Shutdown: 0) or `stop` is set (Goodbye, 0), and returns
// the process exit code. Whoever sets `stop` must then call wake.notify().
int run_worker(const LoopSettings& settings, WakePipe& wake, const std::atomic<bool>& stop);

}  // namespace poet::worker
