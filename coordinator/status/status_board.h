#pragma once
// The coordinator's status board: what the status socket shows, published by the run loop (after each iteration
// and at start) and by the dispatcher (from any thread), read by the HTTP server's threads. Publishers build a
// small snapshot outside the lock (the pairs' scores and lineage, never θ or the optimizer) and swap it in;
// readers take a view (board_view.h: references to the current snapshots) under the lock and build their
// messages outside it (status_messages, prometheus_text), so the lock is held for a pointer swap or copy and the
// run never waits on a reader, whatever the reader does. The files of the run directory (events.jsonl,
// pair_stats.csv) are read by readers alone, outside that lock, with report/'s readers of those files.
// Thread-safe: every member may be called from any thread.

#include <chrono>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "common/protocol/status_defaults.h"
#include "coordinator/status/board_view.h"
#include "coordinator/status/run_picture_cache.h"
#include "engine/run_state.h"
#include "run_directory/reading/pair_stats_log.h"
#include "status.pb.h"

namespace poet {

// "starting", "running", "waiting_for_workers", "stopping", "finished".
std::string_view to_string(RunPhase phase);

// The publishes the rates are measured over (the current one and the ones before it).
inline constexpr size_t kRateWindow = 5;

class StatusBoard {
 public:
  using Clock = std::function<std::chrono::steady_clock::time_point()>;

  // run_dir: where events.jsonl and pair_stats.csv are read from. clock: steady_clock::now unless a test gives
  // its own (rates, uptime and heartbeat ages are measured on it).
  explicit StatusBoard(std::filesystem::path run_dir, Clock clock = {});
  StatusBoard(const StatusBoard&) = delete;
  StatusBoard& operator=(const StatusBoard&) = delete;

  // The run's state: at start and after each iteration. last_checkpoint_iteration is the next_iteration of the
  // last checkpoint written. Copies the pairs' summaries and lineage (not θ, not the optimizer): O(pairs).
  void publish_run(const RunState& state, int last_checkpoint_iteration);
  // The dispatcher's state; replaces the previous one.
  void publish_dispatch(DispatchView snapshot);
  // The phase and a free-text note (empty clears it). The board starts in kStarting.
  void set_state(RunPhase phase, std::string note = "");
  // A file of the CURVE authorized/ folder was found to hold no key, and skipped (counted once per file).
  void count_skipped_key_file();
  // The episodes the score cache answered without running them, and their environment steps, so far.
  void publish_cache(int64_t episodes_saved, int64_t steps_saved);
  // The seconds this process has spent in each phase of an iteration (poet/phase_observer.h), so far.
  // This process's seconds in each phase of an iteration, and those spent waiting for rollouts, as of the last save.
  void publish_phases(const PhaseSeconds& seconds, double waiting);

  // What the board holds now.
  BoardView view() const;

  // GET /status.
  status::Status status() const;
  // GET /pairs: every pair, in creation order.
  status::PairList pairs() const;
  // GET /pairs/{id}: the pair with its scores (from pair_stats.csv) and lineage; nullopt for an unknown id.
  std::optional<status::PairDetail> pair(int id) const;
  // Whether the run has a pair with this id: pair(id) without reading its scores.
  bool has_pair(int id) const;
  // GET /archive.
  status::Archive archive() const;
  // GET /workers.
  status::WorkerList workers() const;
  // GET /events?since=N: lines [since, since + limit) of events.jsonl (complete lines only; limit is clamped to
  // [1, kMaxEventsPerPage]). A line that is not a JSON object is shown as {"unparsed": line}. No file yet: no
  // events. An error only when the file exists and cannot be read. Precondition: since >= 0.
  Expected<status::EventList> events(int64_t since, int64_t limit = kMaxEventsPerPage) const;
  // GET /metrics: Prometheus text format 0.0.4.
  std::string metrics_text() const;

  const std::filesystem::path& run_dir() const { return run_dir_; }
  // GET /pictures/... and /pairs/{id}/episode: rendered from the run directory's last checkpoint.
  const RunPictureCache& pictures() const { return pictures_; }

 private:
  struct RateSample {
    std::chrono::steady_clock::time_point at;
    int64_t rollouts = 0;
    int64_t env_steps = 0;
  };

  const std::filesystem::path run_dir_;
  const RunPictureCache pictures_{run_dir_};
  const Clock clock_;
  const std::chrono::steady_clock::time_point created_;

  mutable std::mutex mutex_;  // guards the members below; held only to copy or swap
  std::shared_ptr<const PublishedRun> run_;
  std::shared_ptr<const DispatchView> dispatch_;
  std::chrono::steady_clock::time_point dispatch_at_;
  RunPhase phase_ = RunPhase::kStarting;
  std::string note_;
  std::deque<RateSample> rate_samples_;  // the last kRateWindow publishes
  int64_t skipped_key_files_ = 0;
  int64_t cached_episodes_ = 0;
  int64_t cached_env_steps_ = 0;
  PhaseSeconds phase_seconds_{};
  double waiting_seconds_ = 0;

  // pair_stats.csv, read on when a reader asks (a second lock, which only readers take)
  mutable std::mutex stats_mutex_;
  mutable PairStatsTail stats_;
};

}  // namespace poet
