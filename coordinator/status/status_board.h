#pragma once
// The coordinator's status board: what the status socket shows, published by the run loop (after each iteration
// and at start) and by the dispatcher (from any thread), read by the HTTP server's threads. Publishers build a
// small snapshot outside the lock (the pairs' scores and lineage, never θ or the optimizer) and swap it in;
// readers take a reference to the current snapshot under the lock and build their messages outside it, so the
// lock is held for a pointer swap or copy and the run never waits on a reader, whatever the reader does.
// The files of the run directory (events.jsonl, pair_stats.csv) are read by readers alone, outside that lock.
// Thread-safe: every member may be called from any thread.

#include <chrono>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dispatch/drop_reason.h"
#include "expected.h"
#include "poet/run_state.h"
#include "status.pb.h"
#include "status/run_picture_cache.h"

namespace poet {

// One worker as the dispatcher sees it.
struct WorkerSnapshot {
  std::string id;       // any bytes: shown as is when printable ASCII, else as hex
  std::string address;  // where it connects from, or the name it gave
  int threads = 0;
  int64_t jobs_done = 0;
  int64_t results_done = 0;
  double seconds_since_heartbeat = 0;  // when published; readers add the time since
  uint64_t fingerprint_digest = 0;
};

// The dispatcher's state, as a copy.
struct DispatchSnapshot {
  std::vector<WorkerSnapshot> workers;
  int64_t queue_depth = 0;
  int64_t in_flight_jobs = 0;
  std::map<std::string, int64_t> dropped_frames;  // by reason (drop_reason.h)
  int64_t workers_joined = 0;                     // Welcomes given since the coordinator started
  int64_t workers_lost = 0;                       // workers removed for silence or a failed send
  int64_t backup_jobs = 0;                        // jobs also sent to a second worker (dispatcher.h)
  int64_t leases_expired = 0;                     // jobs taken back from workers not yet proven
  int64_t workers_demoted = 0;                    // workers not proven given no more jobs
  int64_t verified_jobs = 0;                      // jobs two workers answered alike
  int64_t unverified_jobs = 0;                    // jobs chosen for a check no other worker was there to make
  int64_t wrong_workers = 0;                      // workers refused for wrong results
};

// What the coordinator is doing, for /status's "state".
enum class RunPhase { kStarting, kRunning, kWaitingForWorkers, kStopping, kFinished };

// "starting", "running", "waiting_for_workers", "stopping", "finished".
std::string_view to_string(RunPhase phase);

// At most this many events in one /events page; a client asks again from `next`.
inline constexpr int64_t kMaxEventsPerPage = 1000;

// The publishes the rates are measured over (the current one and the ones before it).
inline constexpr size_t kRateWindow = 5;

// The text with every byte that is not part of valid UTF-8 replaced by '?' (protobuf's JSON printer refuses
// invalid UTF-8; names come from config files, paths from clients).
std::string valid_utf8(std::string_view text);

// A message as one line of JSON (and '\n'): protobuf's JSON mapping with the .proto's field names, zeros printed.
std::string status_json(const google::protobuf::Message& message);

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
  void publish_dispatch(DispatchSnapshot snapshot);
  // The phase and a free-text note (empty clears it). The board starts in kStarting.
  void set_state(RunPhase phase, std::string note = "");
  // A file of the CURVE authorized/ folder was found to hold no key, and skipped (counted once per file).
  void count_skipped_key_file();

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
  // A pair without its θ and optimizer, and the environment's difficulty, computed once.
  struct PairInfo {
    Pair pair;  // theta, best_theta and optimizer left empty
    int difficulty_level = 0;
  };
  // What publish_run copies in.
  struct RunSnapshot {
    RunMode mode = RunMode::kPoet;
    uint64_t seed = 0;
    int next_iteration = 0;
    int iterations = 0;
    bool finished = false;
    RunCounters counters;
    int last_checkpoint_iteration = 0;
    std::vector<PairInfo> pairs;
  };
  struct RateSample {
    std::chrono::steady_clock::time_point at;
    int64_t rollouts = 0;
    int64_t env_steps = 0;
  };
  // What a reader takes out under the lock.
  struct View {
    std::shared_ptr<const RunSnapshot> run;
    std::shared_ptr<const DispatchSnapshot> dispatch;
    std::chrono::steady_clock::time_point dispatch_at;
    RunPhase phase = RunPhase::kStarting;
    std::string note;
    double rollouts_per_s = 0;
    double env_steps_per_s = 0;
    int64_t skipped_key_files = 0;
  };
  // The rows of pair_stats.csv read so far, by pair; read on from `offset` when a reader asks (a second lock,
  // which only readers take).
  struct ScoreRow {
    int iteration = 0;
    double score = 0;
    double best_score = 0;
  };
  struct StatsCache {
    uint64_t offset = 0;  // bytes consumed: whole lines only
    int iteration_column = -1, pair_column = -1, score_column = -1, best_column = -1;  // from the header
    std::map<int, std::vector<ScoreRow>> rows;
  };

  View view() const;
  status::PairSummary summary(const PairInfo& info) const;
  std::vector<ScoreRow> scores_of(int id) const;
  void read_stats() const;  // under stats_mutex_
  void read_stats_line(std::string_view line) const;

  const std::filesystem::path run_dir_;
  const RunPictureCache pictures_{run_dir_};
  const Clock clock_;
  const std::chrono::steady_clock::time_point created_;

  mutable std::mutex mutex_;  // guards the members below; held only to copy or swap
  std::shared_ptr<const RunSnapshot> run_;
  std::shared_ptr<const DispatchSnapshot> dispatch_;
  std::chrono::steady_clock::time_point dispatch_at_;
  RunPhase phase_ = RunPhase::kStarting;
  std::string note_;
  std::deque<RateSample> rate_samples_;  // the last kRateWindow publishes
  int64_t skipped_key_files_ = 0;

  mutable std::mutex stats_mutex_;
  mutable StatsCache stats_;
};

}  // namespace poet
