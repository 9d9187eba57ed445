#pragma once
// The scheduling logic of the remote evaluator, without sockets: a batch of rollout tasks cut into jobs, a queue,
// leases held by workers, liveness by heartbeat (the zguide's Paranoid Pirate), re-queueing of the jobs of a dead
// or departed worker, results matched by job id with duplicates and strangers dropped, the poison-job rule, and
// backup jobs: once the queue is empty, a job held much longer than this batch's jobs take is also sent to a
// worker with a free slot, and the first result wins (every worker computes the same numbers), so a worker that
// heartbeats but never answers, or a slow machine, delays a batch by a bounded time instead of stopping the run.
// Time is a parameter (milliseconds on any monotonic clock), so tests drive it with a fake clock. Not
// thread-safe: the remote evaluator's socket thread owns it under its lock.

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rollout_task.h"
#include "wire.pb.h"

namespace poet {

using Millis = int64_t;
using WorkerId = std::string;  // the ROUTER's routing id of the worker's socket

struct DispatchSettings {
  Millis heartbeat_ms = 1000;  // send something to each worker at least this often (and ask the same of them)
  Millis liveness_ms = 5000;   // a worker silent this long is dead; its jobs go back to the queue
  int max_attempts = 3;        // a task whose worker died this many times stops the run (the first + 2 retries)
  int jobs_ahead = 2;          // jobs a worker holds at once: one running, one arriving
  int max_chunk = 64;          // tasks per job at most
  // A job is backed up once held longer than backup_factor × the median time of this batch's finished jobs (at
  // least backup_min_ms), or than liveness_ms while none has finished. 0: never.
  double backup_factor = 4;
  Millis backup_min_ms = 1000;
  size_t max_workers = 4096;        // Hellos beyond this many connected workers are refused
  uint64_t fingerprint_digest = 0;  // workers of another build are refused (0: accept any, for tests)
};

// A message for one worker.
struct Outgoing {
  WorkerId worker;
  wire::CoordinatorMessage message;
};

struct WorkerView {
  WorkerId id;
  std::string name;
  int threads = 0;
  uint64_t fingerprint_digest = 0;
  int64_t jobs_done = 0;
  int64_t results_done = 0;
  Millis last_heard = 0;
  size_t jobs_held = 0;
};

class Dispatcher {
 public:
  explicit Dispatcher(DispatchSettings settings) : settings_(settings) {}

  // A Hello: the Welcome to send, or a Refused (wrong protocol version or build fingerprint, or max_workers
  // reached; counted). A welcomed worker gets jobs once it has sent another message (proof that it listens).
  wire::CoordinatorMessage on_hello(const WorkerId& id, const wire::Hello& hello, Millis now);
  // A Result from a worker: accepted when the worker holds the job; otherwise counted and dropped.
  void on_result(const WorkerId& id, const wire::Result& result, Millis now);
  // Any message from a known worker proves it alive; false for a stranger (the caller counts and drops it).
  bool heard_from(const WorkerId& id, Millis now);
  // A worker that left (Goodbye, or its socket is gone): its jobs go back to the front of the queue.
  void remove_worker(const WorkerId& id, bool died);

  // Workers silent for liveness_ms are removed (their jobs re-queued, counted as a death for each job).
  std::vector<WorkerId> expire(Millis now);
  // The jobs to send now (each worker filled up to jobs_ahead) and the heartbeats due.
  std::vector<Outgoing> outgoing(Millis now);

  // A new batch (the previous one must be done or abandoned). Tasks are copied; θ is shared, not copied.
  void start_batch(std::span<const RolloutTask> tasks);
  void abandon_batch();
  bool batch_done() const { return batch_active_ && remaining_ == 0; }
  // The results in task order; ends the batch.
  std::vector<RolloutResult> take_results();
  // The ranges [first, end) of tasks whose results became final since the last call, and those results.
  std::vector<std::pair<size_t, size_t>> take_ready_ranges();
  std::span<const RolloutResult> results(size_t first, size_t end) const {
    return std::span<const RolloutResult>(results_).subspan(first, end - first);
  }
  // Set when a task killed max_attempts workers, or a worker refused a task: the run must stop.
  const std::optional<std::string>& failure() const { return failure_; }

  size_t worker_count() const { return workers_.size(); }
  size_t ready_workers() const;  // those that may be sent jobs
  int64_t queue_depth() const { return static_cast<int64_t>(queue_.size()); }
  int64_t in_flight() const;
  std::vector<WorkerView> workers() const;
  // Frames and Hellos refused or dropped, by reason (status_board.h's kDropReasonNames).
  const std::map<std::string, int64_t>& dropped() const { return dropped_; }
  int64_t workers_joined() const { return joined_; }  // Welcomes given
  int64_t workers_lost() const { return lost_; }      // workers removed for silence
  int64_t backup_jobs() const { return backups_; }    // jobs sent to a second worker
  void count_drop(const std::string& reason) { dropped_[reason] += 1; }
  const DispatchSettings& settings() const { return settings_; }

 private:
  struct Lease {
    WorkerId worker;
    Millis since = 0;
  };
  struct Job {
    uint64_t id = 0;
    size_t begin = 0;  // tasks [begin, end) of the batch
    size_t end = 0;
    int deaths = 0;             // workers that died holding it
    std::vector<Lease> leases;  // its holders: none while queued, a second once backed up
  };
  struct Worker {
    WorkerView view;
    std::set<uint64_t> jobs;         // held
    std::set<uint64_t> beaten;       // held, then finished by the other holder first: its result is late
    std::set<uint64_t> thetas_sent;  // this batch
    Millis last_sent = 0;
    bool ready = false;  // has sent something since its Hello
  };

  // The worker no longer holds the job; a job no one holds any more goes back to the queue.
  void release(uint64_t job_id, const WorkerId& id, bool died);
  void requeue(uint64_t job_id, bool died);
  void send(Job& job, const WorkerId& id, Millis now, std::vector<Outgoing>& out);
  // The job to back up on worker id, if any is held past the backup time.
  Job* straggler(const WorkerId& id, Millis now);
  wire::Job job_message(const Job& job, Worker& worker) const;
  std::string describe_task(size_t index) const;

  DispatchSettings settings_;
  std::unordered_map<WorkerId, Worker> workers_;
  std::vector<WorkerId> arrival_;  // workers in the order they said Hello: jobs go out in this order

  // the batch
  bool batch_active_ = false;
  uint64_t batch_id_ = 0;
  std::vector<RolloutTask> tasks_;
  std::vector<uint64_t> task_theta_hash_;
  std::unordered_map<uint64_t, const std::vector<double>*> thetas_;  // by hash
  std::vector<RolloutResult> results_;
  std::vector<bool> have_result_;
  size_t remaining_ = 0;
  std::vector<std::pair<size_t, size_t>> ready_ranges_;
  std::map<uint64_t, Job> jobs_;  // open jobs by id
  std::deque<uint64_t> queue_;
  uint64_t next_job_id_ = 1;
  std::vector<Millis> job_times_;  // how long this batch's finished jobs took, from send to result
  Millis backup_after_ = 0;        // the backup time from job_times_ (0: none finished yet)

  std::optional<std::string> failure_;
  std::map<std::string, int64_t> dropped_;
  int64_t joined_ = 0;
  int64_t lost_ = 0;
  int64_t backups_ = 0;
};

}  // namespace poet
