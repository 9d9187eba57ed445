#include "worker/worker_command.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "common/plumbing/curve_keys.h"
#include "common/plumbing/host_name.h"
#include "common/plumbing/local_token.h"
#include "common/plumbing/stop_signals.h"
#include "common/plumbing/zmq_endpoint.h"
#include "common/program/build_fingerprint.h"
#include "common/program/tool_flags.h"
#include "worker/job_runner.h"
#include "worker/worker_loop.h"

namespace poet::worker {
namespace {

// "host:pid", the default name.
std::string default_name() { return poet::host_name() + ":" + std::to_string(::getpid()); }

// poet-worker's command line; --connect goes straight into the loop's settings.
struct Options {
  LoopSettings settings;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::string name;
  std::string log_level = "info";
  std::string curve_keys;
  int parent_pid = 0;
};

// Parses the command line into `o`. nullopt: go on; otherwise the exit code (as parse_command_line).
std::optional<int> parse_options(int argc, char** argv, Options& o, const WorkerProgram& program) {
  CLI::App app{"A POET worker: runs the rollouts a poet-coordinator sends it"};
  auto* connect =
      app.add_option(
             "--connect", o.settings.endpoint,
             "The coordinator's job endpoint, tcp://HOST:PORT (default: none; this or --coordinator-file is needed)")
          ->check(CLI::Validator(
              [](const std::string& endpoint) {
                return zmq_endpoint_problem(endpoint, EndpointUse::kConnect).value_or(std::string());
              },
              "ENDPOINT"));
  auto* file = app.add_option("--coordinator-file", o.settings.endpoint_file,
                              "Instead of --connect: the coordinator.endpoint file its run directory holds while it "
                              "runs (on a shared file system), read again each time the coordinator is lost, so a "
                              "coordinator that moves (a chained run's next job) is followed; with CURVE it gives "
                              "the coordinator's public key too (default: none)")
                   ->excludes(connect);
  connect->excludes(file);
  app.add_option("--threads", o.threads, "Episodes run at once (default: hardware concurrency)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--name", o.name, "Name in the coordinator's logs (default: host:pid)");
  app.add_option("--curve-keys", o.curve_keys,
                 "CURVE authentication: DIR holds worker.key(_secret), this worker's pair, and coordinator.key, the "
                 "coordinator's public key (made by `poetctl keygen`) (default: none)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error or off")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
  app.add_option("--parent-pid", o.parent_pid,
                 "Exit when process PID, the coordinator that started this worker, is gone (--local-workers)")
      ->check(CLI::Range(1, INT_MAX))
      ->group("");
  poet::add_fingerprint_flag(app);
  if (program.add_options) program.add_options(app);
  if (std::optional<int> code = poet::parse_command_line(app, argc, argv)) return code;
  if (connect->count() + file->count() == 0) {
    std::fprintf(stderr, "give --connect tcp://HOST:PORT or --coordinator-file FILE\n");
    return poet::kExitUsage;
  }
  return std::nullopt;
}

// A local worker ends with its coordinator, however that ends (a SIGKILL included): the kernel sends SIGTERM
// when the parent goes, and a parent gone before this is seen as a changed parent pid. False: gone already.
bool follow_parent(int parent_pid) {
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent_pid) {
    spdlog::warn("the coordinator that started this worker (pid {}) is gone: exiting", parent_pid);
    return false;
  }
  return true;
}

// The keys in the --curve-keys directory: the worker's own pair and the coordinator's public key, which a worker
// given --coordinator-file may leave to that file (empty here: the file must have it).
poet::Expected<CurveClient> curve_client(const std::string& dir, bool key_in_endpoint_file) {
  poet::Expected<poet::CurveKeyPair> own = poet::read_key_pair(dir, "worker");
  if (!own) return poet::Unexpected{own.error()};
  const std::filesystem::path coordinator_key = std::filesystem::path(dir) / "coordinator.key";
  if (key_in_endpoint_file && !std::filesystem::exists(coordinator_key))
    return CurveClient{"", own->public_key, own->secret_key};
  poet::Expected<std::string> coordinator = poet::read_key_file(coordinator_key);
  if (!coordinator) return poet::Unexpected{coordinator.error()};
  return CurveClient{*coordinator, own->public_key, own->secret_key};
}

// What the worker says of itself in its Hellos: threads, name and the local token.
void set_session(Options& o) {
  SessionSettings& session = o.settings.session;
  session.threads = static_cast<uint32_t>(o.threads);
  session.name = o.name.empty() ? default_name() : o.name;
  // a worker started by --local-workers gets the coordinator's secret in its environment, not its command line
  if (const char* token = std::getenv(poet::kLocalTokenVariable)) {
    session.local_token = token;
    ::unsetenv(poet::kLocalTokenVariable);
  }
}

}  // namespace

int worker_main(int argc, char** argv, const WorkerProgram& program) {
  // first of all, so that every thread started later has the signals blocked; before the loop a signal ends the
  // worker at once with 0 (there is nothing to say goodbye to)
  static poet::StopSignals signals(0);
  // SIGUSR1 asks a coordinator to stop at a boundary; a scheduler may send it to every process of a job (scancel
  // --signal=USR1), and a worker must not die of it while the coordinator finishes its iteration
  std::signal(SIGUSR1, SIG_IGN);

  Options o;
  if (const std::optional<int> code = parse_options(argc, argv, o, program)) return *code;
  spdlog::set_default_logger(spdlog::stderr_color_mt("poet-worker"));
  spdlog::set_level(spdlog::level::from_str(o.log_level));
  if (o.parent_pid != 0 && !follow_parent(o.parent_pid)) return 0;

  LoopSettings& settings = o.settings;
  if (!o.curve_keys.empty()) {
    poet::Expected<CurveClient> curve = curve_client(o.curve_keys, !settings.endpoint_file.empty());
    if (!curve) {
      spdlog::error("--curve-keys: {} (make keys with `poetctl keygen`)", curve.error());
      return poet::kExitUsage;
    }
    settings.curve = *curve;
  }
  set_session(o);
  spdlog::info(
      "{}: {} threads, connecting to {}; build digest {:016x}, arithmetic {:016x} ({})", settings.session.name,
      o.threads,
      settings.endpoint_file.empty() ? settings.endpoint : "the coordinator " + settings.endpoint_file + " names",
      poet::build_fingerprint_digest(), poet::arithmetic_digest(), poet::arithmetic_text());

  try {
    static poet::WakePipe wake;  // static: the signal thread may still touch it while the process ends
    static std::atomic<bool> stop{false};
    const auto notify = [] { wake.notify(); };
    const std::unique_ptr<JobExecutor> jobs =
        program.make_jobs ? program.make_jobs(o.threads, notify) : std::make_unique<JobRunner>(o.threads, notify);
    signals.loop_started([] {
      stop = true;
      wake.notify();
    });
    return run_worker(settings, *jobs, wake, stop);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return poet::kExitError;
  }
}

}  // namespace poet::worker
