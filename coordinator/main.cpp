// poet-coordinator: runs POET (or one of the paper's controls) in a run directory, its rollouts on threads of this
// process or on poet-worker processes over ZeroMQ.
//   poet-coordinator --config FILE --run-dir DIR [--threads N] [--iterations N] [--start-from POLICY]   a new run
//   poet-coordinator --run-dir DIR --resume [--iterations N]                       continue it (N may extend it)
//   poet-coordinator --run-dir DIR --resume --from-pack FILE      restore a packed run (poetctl pack) into DIR, go on
//   ... [--local-workers N] [--listen tcp://HOST:PORT [--curve-keys DIR | --open-port]] [--status-address HOST:PORT]
//       [--health-address HOST:PORT]
// The state is checkpointed every checkpoint_interval iterations and at the end. SIGINT/SIGTERM abandon the
// iteration in flight (within a second) and exit 128 + the signal's number, the last checkpoint being the state; a
// resume repeats that iteration exactly. A signal during start-up (reading the config or checkpoint, opening the
// run) exits so at once, and so does a second signal. SIGUSR1 or `poetctl stop --at-boundary` (a request file in
// the run directory) stop it at the next iteration boundary instead: the iteration in flight finished and saved,
// exit 3. With --listen it writes coordinator.endpoint into the run directory while it runs, where workers given
// --coordinator-file find it. Exit codes: 0 done, 1 runtime error (or a diverged run), 2 bad command line, config or
// run directory (or one another process owns), 3 stopped at an iteration boundary as asked (not finished), 130
// interrupted by SIGINT, 143 by SIGTERM.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <climits>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "common/plumbing/stop_signals.h"
#include "common/plumbing/zmq_endpoint.h"
#include "common/program/build_fingerprint.h"
#include "common/program/tool_flags.h"
#include "coordinator/daemon/daemon_options.h"
#include "coordinator/daemon/descriptor_limit.h"
#include "coordinator/daemon/endpoint_announcement.h"
#include "coordinator/daemon/rollouts.h"
#include "coordinator/daemon/run_loop.h"
#include "coordinator/daemon/run_opening.h"
#include "coordinator/evaluator/remote_evaluator.h"
#include "coordinator/status/status_server.h"
#include "run_directory/files/run_pack.h"
#include "run_directory/files/wall_times.h"

namespace poet {
namespace {

// Set-up: the status socket, the rollouts' socket, the run opened (restored from a pack first, when asked), the
// servers started and the local workers; then the loop.
int run(const DaemonOptions& options, StopSignals& signals) {
  const auto started = std::chrono::steady_clock::now();
  spdlog::debug("build fingerprint {:016x}", build_fingerprint_digest());
  // the status socket and the probes' listener: a snapshot published after each iteration, read by the servers'
  // own threads; each holds at most its caps' worth of descriptors, fitted into the process's limit
  StatusServerOptions status_options;
  StatusServerOptions health_options = health_listener_options();
  const uint64_t descriptors = raise_descriptor_limit();
  if (fit_listeners(descriptors, status_options, health_options))
    spdlog::warn(
        "this process may open {} file descriptors (its hard RLIMIT_NOFILE): the status socket holds at most {} "
        "connections at once and the health listener {}; a limit of {} keeps their defaults",
        descriptors, status_options.caps.total, health_options.caps.total,
        2 * (descriptors_needed(StatusServerOptions{}) + descriptors_needed(health_listener_options())));
  StatusBoard board(options.run_dir);
  StatusServer server(board, status_options);
  StatusServer health(board, health_options);
  // declared after the board, so the socket thread that publishes to it stops first; bound before the run is
  // opened, so that a port in use changes no file
  std::optional<Rollouts> rollouts = make_rollouts(options, signals, board);
  if (!rollouts) return kExitUsage;
  if (!options.from_pack.empty()) {
    const Expected<PackSummary> restored = restore_run_pack(options.from_pack, options.run_dir);
    if (!restored) {
      spdlog::error("--from-pack {}", restored.error());
      return kExitUsage;
    }
    spdlog::info("restored the run packed in {} into {} (its state at iteration {})", options.from_pack,
                 options.run_dir, restored->next_iteration);
  }
  std::optional<std::pair<RunDirectory, RunState>> opened = options.resume ? resume_run(options) : start_run(options);
  if (!opened) return kExitUsage;
  std::optional<EndpointAnnouncement> announcement;  // the run directory is this process's now: say where it listens
  if (rollouts->remote && !options.listen.empty())
    announcement.emplace(options.run_dir, rollouts->remote->endpoint(), options.advertise_host,
                         rollouts->curve_public_key);
  for (const std::string& repair : opened->first.repairs()) spdlog::warn("{}", repair);
  std::string wall_warning;
  WallTimes wall_times = WallTimes::open(options.run_dir, opened->second.next_iteration, &wall_warning);
  if (!wall_warning.empty()) spdlog::warn("{}", wall_warning);

  board.publish_run(opened->second, opened->second.next_iteration);
  board.set_state(RunPhase::kRunning);
  auto serve = [](StatusServer& s, const std::string& address, const char* name, const char* path) {
    if (address.empty()) return;
    const Expected<int> port = s.start(address);
    if (port) {
      spdlog::info("{}: http://{}:{}{}", name, address.substr(0, address.rfind(':')), *port, path);
    } else {
      spdlog::warn("no {} socket: {}", name, port.error());  // the run goes on without it
    }
  };
  serve(server, options.status_address, "status", "/status");
  serve(health, options.health_address, "health", "/healthz");
  if (rollouts->remote && !start_local_workers(options, *rollouts)) return kExitUsage;
  if (rollouts->remote) {
    rollouts->remote->on_snapshot([&board](DispatchView view) {
      const bool waiting = view.ready_workers == 0 && view.queue_depth > 0;
      board.publish_dispatch(std::move(view));
      board.set_state(waiting ? RunPhase::kWaitingForWorkers : RunPhase::kRunning,
                      waiting ? "no worker is connected" : "");
    });
  }
  const RunEnd end =
      run_loop(options, signals, board, *rollouts->evaluator, std::move(*opened), std::move(wall_times), started);
  end_rollouts(options, signals, board, *rollouts, end.finished, end.finished_when_opened);
  return end.exit_code;
}

}  // namespace
}  // namespace poet

int main(int argc, char** argv) {
  // first of all, so that a signal at any later point of start-up ends the process (130 or 143)
  static poet::StopSignals signals(-1, /*boundary_signal=*/true);

  poet::DaemonOptions options;
  CLI::App app{"Run POET (or a control) in a run directory; resume it after an interruption"};
  auto* config = app.add_option("--config", options.config_path,
                                "Run config (protobuf text format) of a new run (default: none, with --resume)");
  app.add_option("--run-dir", options.run_dir, "The run directory")->required();
  app.add_option("--threads", options.threads, "Rollout threads (default: hardware concurrency)")
      ->check(CLI::Range(1, 4096));
  int iterations = 0;
  auto* iterations_option =
      app.add_option("--iterations", iterations,
                     "Override the config's iteration limit; on resume it may extend it (default: the config's)")
          ->check(CLI::Range(0, INT_MAX));
  auto* resume = app.add_flag("--resume", options.resume, "Continue the run in --run-dir")->excludes(config);
  app.add_option("--from-pack", options.from_pack,
                 "With --resume: first restore the run packed in this file (`poetctl pack`) into --run-dir, which must "
                 "not exist or be empty (default: none)")
      ->needs(resume);
  app.add_option("--start-from", options.start_from,
                 "A new run's first pair starts from this policy ([[θ...], score] as written in policies/) (default: "
                 "none, random parameters)")
      ->needs(config);
  app.add_flag("--quiet", options.quiet, "No progress line");
  app.add_option("--listen", options.listen,
                 "Run rollouts on workers that connect here, e.g. tcp://0.0.0.0:5555 (default: none, rollouts on this "
                 "process's threads, or a free loopback port with --local-workers)")
      ->check(CLI::Validator(
          [](const std::string& endpoint) {
            return poet::zmq_endpoint_problem(endpoint, poet::EndpointUse::kBind).value_or("");
          },
          "ENDPOINT"));
  app.add_option("--advertise-host", options.advertise_host,
                 "The host name or address workers reach this machine by, written for a --listen on every address "
                 "(0.0.0.0, *) into the run directory's coordinator.endpoint (default: this machine's host name)")
      ->check(CLI::Validator(
          [](const std::string& host) {
            // what a worker can connect to: a name, an IPv4 address or a bracketed IPv6 one
            return poet::zmq_endpoint_problem("tcp://" + host + ":1", poet::EndpointUse::kConnect).has_value()
                       ? "not a host name or address a worker can connect to (an IPv6 address goes in brackets)"
                       : "";
          },
          "HOST"));
  app.add_option("--local-workers", options.local_workers, "Start and supervise N poet-worker processes here")
      ->capture_default_str()
      ->check(CLI::Range(0, 256));
  app.add_option("--liveness-ms", options.liveness_ms, "A worker silent this long is dead")
      ->capture_default_str()
      ->check(CLI::Range(50, 600'000));
  double verify_fraction = 0;
  auto* verify_option =
      app.add_option("--verify-fraction", verify_fraction,
                     "Fraction of the jobs of workers not started here that a second worker runs too; results must "
                     "match bit for bit, and a worker found wrong is refused (default 0.05 with --listen without "
                     "--curve-keys, else 0)")
          ->check(CLI::Range(0.0, 1.0));
  app.add_option("--worker-binary", options.worker_binary, "poet-worker for --local-workers (default: beside this)");
  app.add_option("--status-address", options.status_address,
                 "HOST:PORT of the HTTP status socket (port 0: any free port; empty: none)")
      ->capture_default_str();
  app.add_option("--health-address", options.health_address,
                 "HOST:PORT of a listener that answers /healthz alone, for liveness probes: clients of the status "
                 "socket, however many or slow, cannot delay it (default: none; /healthz is on the status socket too)");
  app.add_option("--linger", options.linger_seconds,
                 "A run found finished when opened stays up this long (seconds), telling each worker that connects "
                 "that the run is finished, so that workers an orchestrator starts beside it exit too")
      ->capture_default_str()
      ->check(CLI::Range(0, 3600));
  app.add_option("--curve-keys", options.curve_keys,
                 "CURVE authentication: DIR holds coordinator.key(_secret) and authorized/*.key, the workers' public "
                 "keys (made by `poetctl keygen`); workers without an authorised key get no connection (default: none)")
      ->check(CLI::ExistingDirectory);
  bool open_port = false;
  app.add_flag("--open-port", open_port,
               "Let --listen take workers on an address other than loopback without --curve-keys: anyone who reaches "
               "the port may join, and verification bounds what one connection can do, not what one party holding "
               "many can")
      ->excludes("--curve-keys");
  auto* log_level = app.add_option("--log-level", options.log_level, "trace, debug, info, warn, error or off")
                        ->capture_default_str()
                        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
  bool verbose = false;
  app.add_flag("--verbose", verbose, "Log every mutation attempt and the dispatcher's details (--log-level debug)")
      ->excludes(log_level);
  poet::add_fingerprint_flag(app);
  if (const std::optional<int> code = poet::parse_command_line(app, argc, argv)) return *code;
  if (verbose) options.log_level = "debug";
  if (iterations_option->count() > 0) options.iterations = iterations;
  if (verify_option->count() > 0) options.verify_fraction = verify_fraction;

  spdlog::set_default_logger(spdlog::stderr_color_mt("poet-coordinator"));
  spdlog::set_level(spdlog::level::from_str(options.log_level));
  if (!options.listen.empty() && options.curve_keys.empty() && !poet::loopback_endpoint(options.listen)) {
    if (!open_port) {
      spdlog::error(
          "--listen {} without --curve-keys would take workers from anyone who reaches the port, and one party may "
          "hold many connections there: give --curve-keys DIR (keys made by `poetctl keygen`), listen on loopback, or "
          "accept an open port with --open-port",
          options.listen);
      return poet::kExitUsage;
    }
    spdlog::warn(
        "--open-port: anyone who reaches {} may join as a worker; verification bounds what one connection "
        "can do, not what one party holding many can",
        options.listen);
  }
  if (!options.resume && options.config_path.empty()) {
    spdlog::error("give --config FILE for a new run, or --resume to continue the run in --run-dir");
    return poet::kExitUsage;
  }
  try {
    return poet::run(options, signals);
  } catch (const std::exception& e) {
    spdlog::error("{}; the last checkpoint in {} stays valid (continue with --resume)", e.what(), options.run_dir);
    return poet::kExitError;
  }
}
