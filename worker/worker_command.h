#pragma once
// poet-worker's command line and run, as a function: its options, logging to stderr, the signals (blocked
// everywhere, taken by one sigwait thread), the CURVE keys, --parent-pid, then the socket loop until it ends. A
// program built on the worker calls it from its main with a WorkerProgram that adds its own options and runs the
// jobs its own way; poet-worker calls it with none.
//   poet-worker --connect tcp://HOST:PORT | --coordinator-file RUN_DIR/coordinator.endpoint
//               [--threads N] [--name NAME] [--curve-keys DIR] [--log-level L]
// Exit codes: 0 shut down or stopped, 1 runtime error, 2 bad command line or refused by the coordinator.

#include <functional>
#include <memory>

#include "worker/job_executor.h"

namespace CLI {
class App;
}

namespace poet::worker {

// What a program built on the worker changes (its log lines still carry poet-worker's name). Either member may be
// left empty.
struct WorkerProgram {
  // Adds the program's options (and, say, its description) to the worker's command line.
  std::function<void(CLI::App&)> add_options;
  // What runs the jobs (default: a JobRunner), made once the command line is read and logging is up: `threads` as
  // --threads gives it, `on_finished` to call (without blocking) whenever an outcome is ready.
  std::function<std::unique_ptr<JobExecutor>(int threads, std::function<void()> on_finished)> make_jobs;
};

// The whole process: call it first in main (before any thread starts, so that all of them have the signals
// blocked) and return what it returns.
int worker_main(int argc, char** argv, const WorkerProgram& program = {});

}  // namespace poet::worker
