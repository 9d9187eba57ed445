// poet-coordinator: runs POET (or one of the paper's controls) in a run directory, its rollouts on threads of this
// process or on poet-worker processes over ZeroMQ.
//   poet-coordinator --config FILE --run-dir DIR [--threads N] [--iterations N] [--start-from POLICY]   a new run
//   poet-coordinator --run-dir DIR --resume [--iterations N]                       continue it (N may extend it)
//   poet-coordinator --run-dir DIR --resume --from-pack FILE      restore a packed run (poetctl pack) into DIR, go on
//   ... [--local-workers N] [--listen tcp://HOST:PORT [--curve-keys DIR]] [--status-address HOST:PORT]
//       [--health-address HOST:PORT]
// The state is checkpointed every checkpoint_interval iterations and at the end. SIGINT/SIGTERM abandon the
// iteration in flight (within a second) and exit 128 + the signal's number, the last checkpoint being the state; a
// resume repeats that iteration exactly. A signal during start-up (reading the config or checkpoint, opening the
// run) exits so at once, and so does a second signal. Exit codes: 0 done, 1 runtime error (or a diverged run), 2 bad
// command line, config or run directory (or one another process owns), 130 interrupted by SIGINT, 143 by SIGTERM.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <utility>

#include "common/build_fingerprint.h"
#include "common/curve_keys.h"
#include "common/event_text.h"
#include "common/local_token.h"
#include "common/policy/policy_file.h"
#include "common/stop_signals.h"
#include "common/text_file.h"
#include "common/tool_flags.h"
#include "common/wire_timing.h"
#include "coordinator/console/progress_display.h"
#include "coordinator/dispatch/local_workers.h"
#include "coordinator/evaluator/caching_evaluator.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "coordinator/evaluator/remote_evaluator.h"
#include "coordinator/evaluator/timed_evaluator.h"
#include "coordinator/status/status_server.h"
#include "engine/engine.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/checkpoint_anchors.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/event_json.h"
#include "run_directory/files/phase_timer.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_pack.h"
#include "run_directory/files/wall_times.h"

namespace poet {
namespace {

constexpr int kExitError = 1;

struct Options {
  std::string config_path;
  std::string run_dir;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::optional<int> iterations;
  bool resume = false;
  std::string from_pack;  // a run pack restored into the (new or empty) run directory before the resume
  bool quiet = false;
  std::string log_level = "info";
  std::string listen;     // workers connect here; empty: rollouts on threads of this process
  int local_workers = 0;  // worker processes to start and supervise on this machine
  int liveness_ms = wire_timing::kLivenessMs;
  std::string worker_binary;
  std::vector<std::string> worker_args;                    // passed to every local worker (tests' fault switches)
  std::string status_address = kCoordinatorStatusAddress;  // the HTTP status socket; empty: none
  std::string health_address;                              // the probes' listener (/healthz alone); empty: none
  std::string curve_keys;                                  // CURVE key directory; empty: no authentication
  std::string start_from;                 // a policy file for the first pair's θ; empty: the init stream
  std::optional<double> verify_fraction;  // default: kListenVerifyFraction with --listen and no CURVE
};

// Workers that connect to --listen without CURVE may be anyone's: this fraction of their jobs is checked by a
// second worker unless --verify-fraction says otherwise (the cost is about this fraction of the rollouts).
constexpr double kListenVerifyFraction = 0.05;

// The level an event is logged at: the events that change the population, and one line per reproduction and
// transfer round, at info; each mutation attempt ("child": dozens a reproduction) at debug (--verbose).
spdlog::level::level_enum log_level_of(const nlohmann::ordered_json& event) {
  const auto name = event.is_object() ? event.find("event") : event.end();
  const bool attempt = event.is_object() && name != event.end() && name->is_string() && *name == "child";
  return attempt ? spdlog::level::debug : spdlog::level::info;
}

void print_summary(const RunState& state, double wall_seconds) {
  int active = 0;
  int solved = 0;
  for (const Pair& pair : state.pairs) {
    active += pair.active() ? 1 : 0;
    solved += pair.solved() ? 1 : 0;
  }
  const RunCounters& c = state.counters;
  std::printf("iterations: %d of %d\n", state.next_iteration, state.settings.iterations);
  std::printf("pairs: %zu created, %d active, %d solved\n", state.pairs.size(), active, solved);
  std::printf("transfers: %lld accepted of %lld attempted\n", static_cast<long long>(c.transfer_successes),
              static_cast<long long>(c.transfer_attempts));
  std::printf("rollouts: %lld, env steps: %lld\n", static_cast<long long>(c.rollouts),
              static_cast<long long>(c.env_steps));
  std::printf("wall time: %.1f s\n", wall_seconds);
  std::fflush(stdout);
}

// A resumed run: the checkpoint's state, with --iterations applied (and recorded in the directory).
std::optional<std::pair<RunDirectory, RunState>> continue_run(Expected<std::pair<RunDirectory, RunState>> resumed,
                                                              const Options& options, std::optional<int> iterations) {
  if (!resumed) {
    spdlog::error("{}", resumed.error());
    return std::nullopt;
  }
  auto& [dir, state] = *resumed;
  if (iterations && (!dir.config().has_iterations() || dir.config().iterations() != *iterations)) {
    pb::RunConfig config = dir.config();
    config.set_iterations(*iterations);
    if (auto error = validate(config)) {
      spdlog::error("--iterations: {}", *error);
      return std::nullopt;
    }
    state.settings = run_settings(config);
    std::optional<std::string> error = dir.write_config(config);
    if (!error) error = dir.save(state);
    if (error) {
      spdlog::error("{}", *error);
      return std::nullopt;
    }
  }
  spdlog::info("resumed {} at iteration {} of {}", options.run_dir, state.next_iteration, state.settings.iterations);
  return std::move(*resumed);
}

// The configs of one run: equal but for the iteration limit, which a resume may change.
bool same_run(pb::RunConfig a, pb::RunConfig b) {
  a.clear_iterations();
  b.clear_iterations();
  return a.SerializeAsString() == b.SerializeAsString();
}

// A new run: the config (with --iterations applied), a fresh directory and its first checkpoint. A directory
// that already holds a run of the same config is resumed (a restarted daemon runs the same command line).
std::optional<std::pair<RunDirectory, RunState>> start_run(const Options& options) {
  Expected<pb::RunConfig> config = load_run_config(options.config_path);
  if (!config) {
    spdlog::error("{}", config.error());
    return std::nullopt;
  }
  if (options.iterations) {
    config->set_iterations(*options.iterations);
    if (auto error = validate(*config)) {
      spdlog::error("--iterations: {}", *error);
      return std::nullopt;
    }
  }
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::path(options.run_dir) / kCheckpointFile, ec)) {
    Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(options.run_dir);
    if (resumed && !same_run(resumed->first.config(), *config)) {
      spdlog::error("{} already holds a run of another config; resume it with --resume, or choose another directory",
                    options.run_dir);
      return std::nullopt;
    }
    return continue_run(std::move(resumed), options, config->iterations());
  }
  std::optional<std::vector<double>> start_theta;
  if (!options.start_from.empty()) {
    Expected<PolicyFile> policy = load_policy(options.start_from);
    if (!policy) {
      spdlog::error("--start-from {}", policy.error());
      return std::nullopt;
    }
    spdlog::info("the first pair starts from {}{}", options.start_from,
                 policy->score ? fmt::format(" (score {:.1f} there)", *policy->score) : "");
    start_theta = std::move(policy->params);
  }
  Expected<RunDirectory> dir = RunDirectory::create(options.run_dir, *config);
  if (!dir) {
    spdlog::error("{}", dir.error());
    return std::nullopt;
  }
  RunState state = initial_state(run_settings(*config), std::move(start_theta));
  if (auto error = dir->save(state)) {
    spdlog::error("{}", *error);
    return std::nullopt;
  }
  spdlog::info("new run in {}: mode {}, seed {}, {} iterations", options.run_dir,
               pb::RunConfig::Mode_Name(config->mode()), config->seed(), config->iterations());
  return std::pair<RunDirectory, RunState>(std::move(*dir), std::move(state));
}

std::optional<std::pair<RunDirectory, RunState>> resume_run(const Options& options) {
  return continue_run(RunDirectory::resume(options.run_dir), options, options.iterations);
}

// Where rollouts run: threads of this process, or workers over ZeroMQ (with local ones started here).
struct Rollouts {
  std::unique_ptr<Evaluator> evaluator;
  RemoteEvaluator* remote = nullptr;
  std::vector<std::string> worker_args;  // for local workers
  std::string local_token;
  std::unique_ptr<LocalWorkers> local_workers;
};

// The job socket's CURVE keys from DIR (common/curve_keys.h), checked before anything listens; local workers
// use DIR's worker key, so it must be there and authorised too.
std::optional<CurveServer> curve_server(const std::filesystem::path& dir, bool local_workers) {
  Expected<CurveKeyPair> keys = read_key_pair(dir, "coordinator");
  // a file of authorized/ that holds no key is skipped, here as at every handshake (curve_authenticator.h)
  Expected<AuthorizedKeys> authorized = scan_authorized_keys(dir);
  if (!keys || !authorized) {
    spdlog::error("--curve-keys: {} (make keys with `poetctl keygen`)", keys ? authorized.error() : keys.error());
    return std::nullopt;
  }
  const std::vector<std::string>& authorized_keys = authorized->keys;
  if (local_workers) {
    Expected<CurveKeyPair> worker = read_key_pair(dir, "worker");
    if (!worker || !std::binary_search(authorized_keys.begin(), authorized_keys.end(), worker->public_key)) {
      spdlog::error("--curve-keys with --local-workers: {}",
                    worker ? "worker.key is not in authorized/" : worker.error());
      return std::nullopt;
    }
  }
  if (authorized_keys.empty())
    spdlog::warn("--curve-keys: no key in {}: no worker can connect until one is added", (dir / "authorized").string());
  spdlog::info("CURVE on: workers need one of the {} keys in {}", authorized_keys.size(),
               (dir / "authorized").string());
  return CurveServer{keys->secret_key, dir, {}, {}};  // the callbacks and files: set by the caller
}

// The evaluator, its socket bound (a port in use or a bad endpoint fails here, before any file is written); local
// workers are started later, by start_local_workers.
std::optional<Rollouts> make_rollouts(const Options& options, StopSignals& signals, StatusBoard& board) {
  Rollouts r;
  if (options.listen.empty() && options.local_workers == 0) {
    r.evaluator = std::make_unique<LocalEvaluator>(options.threads, signals.token());
    return r;
  }
  DispatchSettings settings;
  settings.liveness_ms = options.liveness_ms;
  settings.heartbeat_ms = wire_timing::heartbeat_ms(options.liveness_ms);
  settings.fingerprint_digest = build_fingerprint_digest();
  settings.local_token = make_local_token();
  settings.verify_fraction = options.verify_fraction.value_or(
      !options.listen.empty() && options.curve_keys.empty() ? kListenVerifyFraction : 0.0);
  settings.verify_secret = make_verify_secret();
  if (settings.verify_fraction > 0)
    spdlog::info("verification: {:g} of the jobs of workers not started here also run on a second worker",
                 settings.verify_fraction);
  const std::string endpoint = options.listen.empty() ? "tcp://127.0.0.1:*" : options.listen;
  std::optional<CurveServer> curve;
  std::vector<std::string> worker_args = options.worker_args;
  if (!options.curve_keys.empty()) {
    curve = curve_server(options.curve_keys, options.local_workers > 0);
    if (!curve) return std::nullopt;
    curve->skipped_key_file = [&board] { board.count_skipped_key_file(); };
    curve->refused_keys_file = std::filesystem::path(options.run_dir) / kRefusedKeysFile;
    worker_args.insert(worker_args.begin(), {"--curve-keys", options.curve_keys});
  }
  Expected<std::unique_ptr<RemoteEvaluator>> remote =
      RemoteEvaluator::bind(endpoint, settings, signals.token(), std::move(curve));
  if (!remote) {
    spdlog::error("{}", remote.error());
    return std::nullopt;
  }
  r.remote = remote->get();
  r.evaluator = std::move(*remote);
  r.worker_args = std::move(worker_args);
  r.local_token = settings.local_token;
  spdlog::info("workers connect to {}", r.remote->endpoint());
  return r;
}

// --local-workers: started once the run is open, connected to the bound socket.
bool start_local_workers(const Options& options, Rollouts& r) {
  if (options.local_workers == 0) return true;
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::max(1, hardware / options.local_workers);
  const std::string binary = options.worker_binary.empty() ? LocalWorkers::default_binary() : options.worker_binary;
  Expected<std::unique_ptr<LocalWorkers>> workers =
      LocalWorkers::start(binary, r.remote->endpoint(), options.local_workers, threads, r.local_token, r.worker_args);
  if (!workers) {
    spdlog::error("{}", workers.error());
    return false;
  }
  r.local_workers = std::move(*workers);
  spdlog::info("started {} local workers ({}) with {} threads each", options.local_workers, binary, threads);
  return true;
}

// The run loop once the run is open: iterations, checkpoints and the wall times, going back to a checkpoint when
// a worker was found wrong (with verification), and the end of the run. It owns the opened run directory and
// state, and the evaluators in front of the rollouts (the score cache and the time spent waiting).
class RunLoop {
 public:
  RunLoop(const Options& options, StopSignals& signals, StatusBoard& board, Rollouts& rollouts,
          std::pair<RunDirectory, RunState> opened, WallTimes wall_times, std::chrono::steady_clock::time_point started)
      : options_(options),
        signals_(signals),
        board_(board),
        rollouts_(rollouts),
        opened_(std::move(opened)),
        wall_times_(std::move(wall_times)),
        started_(started),
        waiting_(
            *rollouts.evaluator,
            [] { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }),
        evaluator_(waiting_, kScoreCacheBytes),
        progress_(!options.quiet),
        phase_timer_([this] { return elapsed(); }),
        saved_iteration_(state().next_iteration),
        verified_(rollouts.remote && rollouts.remote->verifies()) {}

  // Iterations until the run is complete or a stop is asked for; then the shutdown. The process's exit code.
  int run() {
    keep_anchor();
    signals_.loop_started();
    while (!run_complete(state()) && !signals_.stop_requested()) {
      if (const std::optional<int> ended = iterate()) return *ended;
    }
    return finish();
  }

 private:
  RunDirectory& dir() { return opened_->first; }  // both replaced in place when the run goes back (go_back)
  RunState& state() { return opened_->second; }
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count(); }

  // One iteration, logged, recorded and saved when due; an exit code when the run must end here.
  std::optional<int> iterate() {
    IterationReport report;
    try {
      report = run_iteration(state(), evaluator_, &phase_timer_);
    } catch (const EvaluationStopped&) {
      // the iteration in flight is abandoned; the state in memory is part-way through it and is not saved
      progress_.finish();
      go_back_if_asked();
      log_summaries();
      spdlog::warn(
          "stopped during iteration {}; the run's state is its checkpoint at iteration {}, and a resume "
          "repeats the iterations since: poet-coordinator --run-dir {} --resume",
          state().next_iteration, saved_iteration_, options_.run_dir);
      return signals_.exit_code();
    } catch (const RunDiverged& e) {
      progress_.finish();
      go_back_if_asked();
      spdlog::error("{} (the checkpoint at iteration {} precedes the divergence)", e.what(), saved_iteration_);
      return kExitError;
    } catch (const std::exception&) {  // the workers' failure, told by the caller
      progress_.finish();
      go_back_if_asked();
      throw;
    }
    if (const std::optional<bool> went = go_back_if_asked()) {
      if (!*went) return kExitError;
      return std::nullopt;
    }
    dir().append(report);
    if (!report.events.empty() && spdlog::should_log(spdlog::level::info)) progress_.clear();
    for (const auto& event : events_json(report)) spdlog::log(log_level_of(event), "{}", describe_event(event));
    const int interval = state().settings.checkpoint_interval;
    if (state().next_iteration % interval == 0 || run_complete(state()) || signals_.stop_requested()) {
      if (!save()) return kExitError;
    }
    progress_.update(state(), report);
    board_.publish_run(state(), saved_iteration_);
    board_.publish_cache(evaluator_.episodes_saved(), evaluator_.steps_saved());
    return std::nullopt;
  }

  // The loop ended: the last iterations saved, the summaries logged, the workers told when the run is finished.
  int finish() {
    // a stop between an iteration's save check and the loop test leaves that iteration unsaved
    if (state().next_iteration != saved_iteration_ && !save()) return kExitError;
    progress_.finish();
    log_summaries();
    if (!run_complete(state())) {
      spdlog::warn("interrupted at iteration {}; continue with: poet-coordinator --run-dir {} --resume",
                   state().next_iteration, options_.run_dir);
      print_summary(state(), elapsed());
      return signals_.exit_code();
    }
    if (budget_reached(state()))
      spdlog::info("run finished at iteration {}: its environment-step budget of {} reached ({} steps)",
                   state().next_iteration, state().settings.env_step_budget, state().counters.env_steps);
    else
      spdlog::info("run finished at iteration {}", state().next_iteration);
    board_.set_state(RunPhase::kFinished);
    if (rollouts_.remote) {
      rollouts_.remote->on_snapshot(nullptr);
      rollouts_.remote->shutdown_workers("the run is finished");
    }
    print_summary(state(), elapsed());
    return 0;
  }

  // With verification, the checkpoint just written, kept in memory while a rollback may need it.
  void keep_anchor() {
    if (!verified_) return;
    Expected<std::string> bytes = read_text_file(dir().path() / kCheckpointFile, kMaxCheckpointBytes);
    if (!bytes) {  // then an older one stands in, which only costs more recomputation
      spdlog::warn("{}: {}", (dir().path() / kCheckpointFile).string(), bytes.error());
      return;
    }
    anchors_.add({rollouts_.remote->batch_id(), state().next_iteration, std::move(*bytes)});
    const std::vector<uint64_t> needed = rollouts_.remote->unchecked_since();
    anchors_.prune(needed);
  }

  bool save() {
    if (auto error = dir().save(state())) {
      progress_.finish();
      spdlog::error("{}", *error);
      return false;
    }
    saved_iteration_ = state().next_iteration;
    keep_anchor();
    // the times are the run's record of its machine, not its state: a failed write is reported, not fatal
    const PhaseSeconds phases = phase_timer_.take();
    const double waited = waiting_.take();
    for (size_t k = 0; k < phases.size(); ++k) phase_totals_[k] += phases[k];
    waiting_total_ += waited;
    board_.publish_phases(phase_totals_, waiting_total_);
    if (auto error = wall_times_.record(state().next_iteration - 1, elapsed() - wall_offset_, phases, waited))
      spdlog::warn("{}", *error);
    return true;
  }

  // Going back: with verification, each checkpoint a rollback may need is kept in memory (checkpoint_anchors.h);
  // when a worker found wrong had unchecked answers taken, the run returns to the newest saved before them and
  // computes again from there without it: deterministic, so the numbers end as if it never joined.
  std::optional<std::string> go_back(uint64_t first_bad) {
    const CheckpointAnchor* anchor = anchors_.before(first_bad);
    if (anchor == nullptr) return "no checkpoint precedes batch " + std::to_string(first_bad);
    progress_.finish();
    spdlog::warn(
        "a worker found wrong had unchecked answers taken since batch {}: the run goes back to its checkpoint at "
        "iteration {} and computes again from there without it",
        first_bad, anchor->next_iteration);
    if (auto error = write_file_atomically(dir().path() / kCheckpointFile, anchor->bytes))
      return (dir().path() / kCheckpointFile).string() + ": " + *error;
    rollouts_.remote->forget_batches_from(anchor->last_batch + 1);
    evaluator_.clear();  // the wrong worker's results may be among those remembered
    anchors_.keep_until(*anchor);
    opened_.reset();  // its lock released, for the resume to take
    Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(options_.run_dir);
    if (!resumed) return resumed.error();
    opened_.emplace(std::move(*resumed));
    std::string warning;
    const double carried_before = wall_times_.carried();
    wall_times_ = WallTimes::open(options_.run_dir, state().next_iteration, &warning);
    wall_offset_ += wall_times_.carried() - carried_before;
    if (!warning.empty()) spdlog::warn("{}", warning);
    saved_iteration_ = state().next_iteration;
    board_.publish_run(state(), saved_iteration_);
    return std::nullopt;
  }

  // Whether the run went back (true), did not need to (nothing), or could not (false; logged). Also asked when the
  // iteration in flight is given up: a liar caught then may have unchecked answers in the checkpoint on disk, which
  // a resume must not go on from.
  std::optional<bool> go_back_if_asked() {
    const std::optional<uint64_t> first_bad = rollouts_.remote ? rollouts_.remote->take_rollback() : std::nullopt;
    if (!first_bad) return std::nullopt;
    if (auto error = go_back(*first_bad)) {
      spdlog::error("going back: {}", *error);
      return false;
    }
    return true;
  }

  // what this process's dispatcher and score cache did, however the loop ends
  void log_summaries() {
    if (rollouts_.remote) rollouts_.remote->log_summary();
    if (evaluator_.episodes_saved() > 0)
      spdlog::info("score cache: {} episodes asked for again were not run ({} environment steps)",
                   evaluator_.episodes_saved(), evaluator_.steps_saved());
  }

  const Options& options_;
  StopSignals& signals_;
  StatusBoard& board_;
  Rollouts& rollouts_;
  std::optional<std::pair<RunDirectory, RunState>> opened_;
  WallTimes wall_times_;
  const std::chrono::steady_clock::time_point started_;
  TimedEvaluator waiting_;      // the loop's time waiting for rollouts; the rest of its time is its own work
  CachingEvaluator evaluator_;  // the cache answers without any
  ProgressDisplay progress_;
  PhaseTimer phase_timer_;
  PhaseSeconds phase_totals_{};  // this process's, for /metrics
  double waiting_total_ = 0;     // the same
  int saved_iteration_;
  CheckpointAnchors anchors_;
  // the run's wall time stays the machine's time after going back: the times of the iterations given up are in it
  double wall_offset_ = 0;
  const bool verified_;
};

// Set-up: the status socket, the rollouts' socket, the run opened (restored from a pack first, when asked), the
// servers started and the local workers; then the loop.
int run(const Options& options, StopSignals& signals) {
  const auto started = std::chrono::steady_clock::now();
  spdlog::debug("build fingerprint {:016x}", build_fingerprint_digest());
  // the status socket and the probes' listener: a snapshot published after each iteration, read by the servers'
  // own threads
  StatusBoard board(options.run_dir);
  StatusServer server(board);
  StatusServer health(board, health_listener_options());
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
  RunLoop loop(options, signals, board, *rollouts, std::move(*opened), std::move(wall_times), started);
  return loop.run();
}

}  // namespace
}  // namespace poet

int main(int argc, char** argv) {
  // first of all, so that a signal at any later point of start-up ends the process (130 or 143)
  static poet::StopSignals signals;

  poet::Options options;
  CLI::App app{"Run POET (or a control) in a run directory; resume it after an interruption"};
  auto* config = app.add_option("--config", options.config_path, "Run config (protobuf text format): a new run");
  app.add_option("--run-dir", options.run_dir, "The run directory")->required();
  app.add_option("--threads", options.threads, "Rollout threads (default: hardware concurrency)")
      ->check(CLI::Range(1, 4096));
  int iterations = 0;
  auto* iterations_option =
      app.add_option("--iterations", iterations, "Override the iteration limit (on resume it may extend it)")
          ->check(CLI::Range(0, INT_MAX));
  auto* resume = app.add_flag("--resume", options.resume, "Continue the run in --run-dir")->excludes(config);
  app.add_option("--from-pack", options.from_pack,
                 "With --resume: first restore the run packed in this file (`poetctl pack`) into --run-dir, which must "
                 "not exist or be empty")
      ->needs(resume);
  app.add_option("--start-from", options.start_from,
                 "A new run's first pair starts from this policy ([[θ...], score] as written in policies/) instead of "
                 "random parameters")
      ->needs(config);
  app.add_flag("--quiet", options.quiet, "No progress line");
  app.add_option("--listen", options.listen,
                 "Run rollouts on workers that connect here (e.g. tcp://0.0.0.0:5555); default with "
                 "--local-workers: a free loopback port");
  app.add_option("--local-workers", options.local_workers, "Start and supervise N poet-worker processes here")
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
  app.add_option("--worker-arg", options.worker_args, "An argument for every local worker (repeatable)")
      ->group("");  // for tests: fault switches
  app.add_option("--status-address", options.status_address,
                 "HOST:PORT of the HTTP status socket (port 0: any free port; empty: none)")
      ->capture_default_str();
  app.add_option("--health-address", options.health_address,
                 "HOST:PORT of a listener that answers /healthz alone, for liveness probes: clients of the status "
                 "socket, however many or slow, cannot delay it (default: none; /healthz is on the status socket too)");
  app.add_option("--curve-keys", options.curve_keys,
                 "CURVE authentication: DIR holds coordinator.key(_secret) and authorized/*.key, the workers' public "
                 "keys (made by `poetctl keygen`); workers without an authorised key get no connection")
      ->check(CLI::ExistingDirectory);
  auto* log_level = app.add_option("--log-level", options.log_level, "trace, debug, info (default), warn, error or off")
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
