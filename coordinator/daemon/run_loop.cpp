#include "coordinator/daemon/run_loop.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "common/plumbing/text_file.h"
#include "common/program/tool_flags.h"
#include "common/text/event_text.h"
#include "coordinator/console/progress_display.h"
#include "coordinator/evaluator/caching_evaluator.h"
#include "coordinator/evaluator/timed_evaluator.h"
#include "engine/engine.h"
#include "run_directory/files/boundary_stop.h"
#include "run_directory/files/checkpoint_anchors.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/event_json.h"
#include "run_directory/files/phase_timer.h"

namespace poet {
namespace {

// The level an event is logged at: the events that change the population, and one line per reproduction and
// transfer round, at info; each mutation attempt (a ChildEvent: dozens a reproduction) at debug (--verbose).
spdlog::level::level_enum log_level_of(const RunEvent& event) {
  return std::holds_alternative<ChildEvent>(event) ? spdlog::level::debug : spdlog::level::info;
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

// The run loop once the run is open: iterations, checkpoints and the wall times, going back to a checkpoint when
// the evaluator withdraws results (a worker found wrong, with verification), and the end of the run. It owns the
// opened run directory and state, and the evaluators in front of the rollouts (the score cache and the time spent
// waiting).
class RunLoop {
 public:
  RunLoop(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Evaluator& rollouts,
          std::pair<RunDirectory, RunState> opened, WallTimes wall_times, std::chrono::steady_clock::time_point started)
      : options_(options),
        signals_(signals),
        board_(board),
        opened_(std::move(opened)),
        wall_times_(std::move(wall_times)),
        started_(started),
        waiting_(
            rollouts,
            [] { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }),
        evaluator_(waiting_, kScoreCacheBytes),
        progress_(!options.quiet),
        phase_timer_([this] { return elapsed(); }),
        saved_iteration_(state().next_iteration),
        finished_when_opened_(run_complete(state())),
        may_go_back_(evaluator_.withdrawals().possible) {}

  // Iterations until the run is complete or a stop is asked for; then the shutdown.
  RunEnd run() {
    keep_anchor();
    signals_.loop_started();
    while (!run_complete(state()) && !signals_.stop_requested()) {
      if (const std::optional<int> ended = iterate()) return {*ended, false, finished_when_opened_};
      if (!run_complete(state()) && !signals_.stop_requested() && boundary_stop_asked()) return stop_at_boundary();
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
    // the line as events.jsonl has it: the log reads like the file
    for (const RunEvent& event : report.events)
      spdlog::log(log_level_of(event), "{}", describe_event(event_json(report.iteration, event)));
    const int interval = state().settings.checkpoint_interval;
    if (state().next_iteration % interval == 0 || run_complete(state()) || signals_.stop_requested()) {
      if (!save()) return kExitError;
    }
    progress_.update(state(), report);
    board_.publish_run(state(), saved_iteration_);
    board_.publish_cache(evaluator_.episodes_saved(), evaluator_.steps_saved());
    return std::nullopt;
  }

  // Whether a stop at this boundary was asked: SIGUSR1 (SLURM's warning before a time limit) or the request file
  // (`poetctl stop --at-boundary`, from any machine that sees the run directory).
  bool boundary_stop_asked() {
    if (signals_.boundary_stop_requested()) {
      boundary_reason_ = "SIGUSR1";
      return true;
    }
    const Expected<bool> requested = boundary_stop_requested(dir().path());
    if (!requested) {
      if (!request_unreadable_logged_)
        spdlog::warn("{}: {}", (dir().path() / kBoundaryStopFile).string(), requested.error());
      request_unreadable_logged_ = true;
      return false;
    }
    if (*requested) boundary_reason_ = (dir().path() / kBoundaryStopFile).string();
    return *requested;
  }

  // A stop at the boundary just reached: the iteration finished and saved, the request removed (so that the next
  // job of a chain runs on), kExitStoppedAtBoundary.
  RunEnd stop_at_boundary() {
    if (state().next_iteration != saved_iteration_ && !save()) return {kExitError, false, finished_when_opened_};
    progress_.finish();
    log_summaries();
    if (auto error = clear_boundary_stop(dir().path()))
      spdlog::warn("{}: {} (remove it, or the next coordinator of this run stops after one iteration)",
                   (dir().path() / kBoundaryStopFile).string(), *error);
    spdlog::info(
        "stopped at the boundary of iterations {} and {} as asked ({}); the checkpoint at iteration {} is the state: "
        "poet-coordinator --run-dir {} --resume",
        state().next_iteration - 1, state().next_iteration, boundary_reason_, saved_iteration_, options_.run_dir);
    print_summary(state(), elapsed());
    return {kExitStoppedAtBoundary, false, finished_when_opened_};
  }

  // The loop ended: the last iterations saved, the summaries logged.
  RunEnd finish() {
    // a stop between an iteration's save check and the loop test leaves that iteration unsaved
    if (state().next_iteration != saved_iteration_ && !save()) return {kExitError, false, finished_when_opened_};
    progress_.finish();
    log_summaries();
    if (!run_complete(state())) {
      spdlog::warn("interrupted at iteration {}; continue with: poet-coordinator --run-dir {} --resume",
                   state().next_iteration, options_.run_dir);
      print_summary(state(), elapsed());
      return {signals_.exit_code(), false, finished_when_opened_};
    }
    if (auto error = clear_boundary_stop(dir().path()))  // a request the last iteration made moot
      spdlog::warn("{}: {}", (dir().path() / kBoundaryStopFile).string(), *error);
    if (budget_reached(state()))
      spdlog::info("run finished at iteration {}: its environment-step budget of {} reached ({} steps)",
                   state().next_iteration, state().settings.env_step_budget, state().counters.env_steps);
    else
      spdlog::info("run finished at iteration {}", state().next_iteration);
    print_summary(state(), elapsed());
    return {0, true, finished_when_opened_};
  }

  // When results may be withdrawn, the checkpoint just written, kept in memory while going back may need it.
  void keep_anchor() {
    if (!may_go_back_) return;
    Expected<std::string> bytes = read_text_file(dir().path() / kCheckpointFile, kMaxCheckpointBytes);
    if (!bytes) {  // then an older one stands in, which only costs more recomputation
      spdlog::warn("{}: {}", (dir().path() / kCheckpointFile).string(), bytes.error());
      return;
    }
    const Withdrawals withdrawals = evaluator_.withdrawals();
    anchors_.add({withdrawals.last_batch, state().next_iteration, std::move(*bytes)});
    anchors_.prune(withdrawals.reachable);
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
    evaluator_.went_back(anchor->last_batch);  // and the score cache forgets: the wrong worker's results may be in it
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
    const std::optional<uint64_t> first_bad = evaluator_.withdrawals().withdrawn_from;
    if (!first_bad) return std::nullopt;
    if (auto error = go_back(*first_bad)) {
      spdlog::error("going back: {}", *error);
      return false;
    }
    return true;
  }

  // what the score cache did, however the loop ends (the workers' part is their owner's: end_rollouts)
  void log_summaries() {
    if (evaluator_.episodes_saved() > 0)
      spdlog::info("score cache: {} episodes asked for again were not run ({} environment steps)",
                   evaluator_.episodes_saved(), evaluator_.steps_saved());
  }

  const DaemonOptions& options_;
  StopSignals& signals_;
  StatusBoard& board_;
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
  const bool finished_when_opened_;  // nothing to run: the process only lingers (--linger) for its workers
  CheckpointAnchors anchors_;
  // the run's wall time stays the machine's time after going back: the times of the iterations given up are in it
  double wall_offset_ = 0;
  const bool may_go_back_;  // the evaluator may withdraw results (verification): checkpoints are kept for it
  std::string boundary_reason_;             // who asked for the stop at the boundary, for the log
  bool request_unreadable_logged_ = false;  // the request file could not be looked for: said once
};

}  // namespace

RunEnd run_loop(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Evaluator& rollouts,
                std::pair<RunDirectory, RunState> opened, WallTimes wall_times,
                std::chrono::steady_clock::time_point started) {
  RunLoop loop(options, signals, board, rollouts, std::move(opened), std::move(wall_times), started);
  return loop.run();
}

}  // namespace poet
