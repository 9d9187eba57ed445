// poet-test-worker: poet-worker with a fault, for the tests of how the coordinator and its verification deal with
// a peer that misbehaves. Its command line is poet-worker's and these:
//   --fault crash-on-job|ignore-jobs|error-on-job|wrong-results
//   --lie-after N  --lie-fraction F  --lie-where-predicted-unchecked      (the shape of wrong-results' lies)
// or, where a coordinator starts it as a local worker (--worker-binary), the environment's
//   POET_TEST_WORKER_FAULT=F    the same as --fault F, unless --fault is given
// Everything but the jobs' fate is the production worker's (worker_main), so a test of the coordinator meets the
// real protocol.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "tests/support/test_worker/faulty_jobs.h"
#include "worker/job_runner.h"
#include "worker/worker_command.h"

namespace {

using poet::test_worker::Fault;

const std::map<std::string, Fault> kFaults = {{"crash-on-job", Fault::kCrashOnJob},
                                              {"ignore-jobs", Fault::kIgnoreJobs},
                                              {"error-on-job", Fault::kErrorOnJob},
                                              {"wrong-results", Fault::kWrongResults}};

struct FaultOptions {
  std::string fault;
  poet::test_worker::LieShape lie;
};

void add_fault_options(CLI::App& app, FaultOptions& o) {
  app.description("poet-worker with a fault, for the coordinator's tests");
  app.add_option("--fault", o.fault,
                 "crash-on-job (abort() on receiving a Job), ignore-jobs (never answer a Job, keep heartbeating), "
                 "error-on-job (answer every Job with an error) or wrong-results (returns off by one)")
      ->check(CLI::IsMember(kFaults));
  app.add_option("--lie-after", o.lie.honest_jobs, "wrong-results: answer the first N jobs honestly")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--lie-fraction", o.lie.fraction, "wrong-results: then lie on this fraction of the jobs (default 1)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--lie-where-predicted-unchecked", o.lie.where_predicted_unchecked,
               "wrong-results: lie only where a public rule of the batch and job ids predicts no check");
}

}  // namespace

int main(int argc, char** argv) {
  static FaultOptions options;
  if (const char* fault = std::getenv("POET_TEST_WORKER_FAULT"); fault != nullptr && *fault != '\0') {
    if (!kFaults.contains(fault)) {
      std::fprintf(stderr, "POET_TEST_WORKER_FAULT=%s: not a fault (crash-on-job, ignore-jobs, error-on-job or "
                   "wrong-results)\n", fault);
      return 2;
    }
    options.fault = fault;
  }
  poet::worker::WorkerProgram program;
  program.add_options = [](CLI::App& app) { add_fault_options(app, options); };
  program.make_jobs = [](int threads, std::function<void()> on_finished) -> std::unique_ptr<poet::worker::JobExecutor> {
    auto runner = std::make_unique<poet::worker::JobRunner>(threads, on_finished);
    if (options.fault.empty()) return runner;
    spdlog::warn("--fault {}: this worker misbehaves on purpose (a test)", options.fault);
    return std::make_unique<poet::test_worker::FaultyJobs>(kFaults.at(options.fault), options.lie, std::move(runner),
                                                           std::move(on_finished));
  };
  return poet::worker::worker_main(argc, argv, program);
}
