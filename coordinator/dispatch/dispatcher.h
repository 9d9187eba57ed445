#pragma once
// The scheduling logic of the remote evaluator, without sockets: a batch of rollout tasks cut into jobs, a queue,
// leases held by workers, liveness by heartbeat (the zguide's Paranoid Pirate), re-queueing of the jobs of a dead
// or departed worker, results matched by job id with duplicates and strangers dropped, the poison-job rule, and
// backup jobs. Time is a parameter (milliseconds on any monotonic clock), so tests drive it with a fake clock. Not
// thread-safe: the remote evaluator's socket thread owns it under its lock. It composes the pieces with one job
// each — WorkerRegistry (who is connected, what each holds, trials), JobQueue (the queue, its leases and backups),
// BatchResults (what is final) and JobEncoder (the wire) — with WorkerTrust (coordinator/trust), and keeps the
// rules that join them: how a batch is cut, whom a job goes to, the poison-job rule.
//
// Who may take which job, what an answer settles and when the run must go back are trust's to say
// (coordinator/trust/worker_trust.h: proven workers, probation, verification, refusals, the coordinator's own checks
// and the rollback record); the Dispatcher acts on those decisions. A worker not proven holds one job at a time, and
// so does one on probation. With nothing queued, a proven worker takes at once a job held only by workers not proven
// (a backup; the first result wins), and a worker not proven gets a copy of an open job as its trial (one at a time,
// across batches until it answers: one that lets a trial run past a lease is demoted). So any number of peers that
// say Hello, heartbeat and never answer cannot queue a real worker behind them, and delay a batch by at most about
// one lease (backup_factor × the median time of the batch's finished jobs, at least backup_min_ms, or liveness_ms
// while none has finished), and by nothing once a proven worker is there. A proven worker's job held past the lease
// is also sent to another worker (up to max_leases holders; the first result wins). The run stops on a poison job
// only when max_attempts proven workers died holding it, and on an error when trust says proven workers agree.
// A job whose answer no connected witness can check (or whose check was held past the lease), answers that differ
// with no witness to decide, or three answers none of which confirms another, go to the coordinator
// (take_coordinator_checks). A worker found wrong is refused from then on (Refused, and its Hellos), and every result
// of the batch taken from it and not yet reported final is computed again; refuse() does the same to a peer the
// caller finds shares its identity (a CURVE key).
// Unchecked answers of workers that are not local are reported final (take_ready_ranges) only once the batch is
// whole; take_rollback names the first batch to compute again when a worker refused had unchecked answers made
// final.

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/plumbing/wire_timing.h"
#include "coordinator/dispatch/batch_results.h"
#include "coordinator/dispatch/dispatch_view.h"
#include "coordinator/dispatch/drop_reason.h"
#include "coordinator/dispatch/hello_check.h"
#include "coordinator/dispatch/job_encoder.h"
#include "coordinator/dispatch/job_queue.h"
#include "coordinator/dispatch/outgoing.h"
#include "coordinator/dispatch/worker_registry.h"
#include "coordinator/trust/worker_trust.h"
#include "simulation/rollout_task.h"
#include "wire.pb.h"

namespace poet {

struct DispatchSettings {
  // send something to each worker at least this often (and ask the same of them)
  Millis heartbeat_ms = wire_timing::kHeartbeatMs;
  Millis liveness_ms = wire_timing::kLivenessMs;  // a worker silent this long is dead; its jobs go back to the queue
  int max_attempts = 3;  // a task whose worker died this many times stops the run (the first + 2 retries)
  int jobs_ahead = 2;    // jobs a worker holds at once: one running, one arriving
  int max_chunk = 64;    // tasks per job at most
  // A job is backed up once held longer than backup_factor × the median time of this batch's finished jobs (at
  // least backup_min_ms), or than liveness_ms while none has finished. 0: never.
  double backup_factor = 4;
  Millis backup_min_ms = 1000;
  int max_leases = 3;          // holders of one job at once: the first and its backups
  size_t max_workers = 4096;   // Hellos beyond this many connected workers are refused
  HelloExpectation build;      // workers of another build or arithmetic are refused (0s: accept any, for tests)
  std::string local_token;     // a Hello carrying it comes from a local worker: proven from the start
  double verify_fraction = 0;  // of the jobs answered by workers that are not local, also run on a second
  uint64_t verify_secret = 0;  // which jobs are checked: drawn from it, the batch and the job; never sent
  int probation_checks = 5;    // with verification: every answer of a worker not local is checked until this many were
};

class Dispatcher {
 public:
  explicit Dispatcher(DispatchSettings settings)
      : settings_(settings),
        jobs_({settings.liveness_ms, settings.backup_factor, settings.backup_min_ms, settings.max_leases}),
        trust_({settings.verify_fraction, settings.verify_secret, settings.probation_checks}) {}

  // A Hello: the Welcome to send, or a Refused (wrong protocol version or build fingerprint, or max_workers
  // reached; counted). A welcomed worker gets jobs once it has sent another message (proof that it listens).
  // `witness`: the CURVE key its connection was admitted with (empty without CURVE: its routing id vouches alone).
  wire::CoordinatorMessage on_hello(const WorkerId& id, const wire::Hello& hello, Millis now,
                                    const Witness& witness = {});
  // A Result from a worker: accepted when the worker holds the job; otherwise counted and dropped.
  void on_result(const WorkerId& id, const wire::Result& result, Millis now);
  // Any message from a known worker proves it alive; false for a stranger (the caller counts and drops it).
  bool heard_from(const WorkerId& id, Millis now);
  // A worker that left (Goodbye, or its socket is gone): its jobs go back to the front of the queue.
  void remove_worker(const WorkerId& id, bool died);

  // A job whose answer no connected worker can check, or two answers that differ with no worker to decide: its
  // tasks, for the coordinator to run itself. Each is handed out once; a worker's answer may still settle it first.
  struct CoordinatorCheck {
    uint64_t batch_id = 0;
    uint64_t job_id = 0;
    bool disputed = false;  // answers that differ (otherwise answers that no connected witness can check)
    std::vector<RolloutTask> tasks;
  };
  std::vector<CoordinatorCheck> take_coordinator_checks();
  // Whether that job still waits for an answer (a worker's may have settled it since it was handed out).
  bool awaits_coordinator(uint64_t batch_id, uint64_t job_id) const;
  // The coordinator's results for such a job: a worker whose answer differs is refused, as one found wrong by a
  // third worker is, those that agree pass a check, and the results are final. Ignored when the job was settled
  // meanwhile or its batch is over.
  void settle_by_coordinator(uint64_t batch_id, uint64_t job_id, const std::vector<RolloutResult>& results);
  // Refuses a worker found wrong, or a peer (registered or not) the caller finds shares a wrong one's identity (its
  // CURVE key): told why ("this worker " + why), its Hellos refused, its results not final redone, the run sent
  // back when unchecked ones became final. The id is a copy: the answers naming it are erased.
  void refuse(WorkerId id, const std::string& why);

  // Going back. batch_id() is the batch started last (0: none yet). take_rollback: the first batch whose final
  // results may hold a lie — a worker was refused after unchecked answers of its from that batch on became final —
  // once; the caller goes back to a state computed before that batch started (what must stay reachable meanwhile
  // is trust().unchecked_since()). forget_batches_from: the caller went back to before `batch`; answers of that
  // batch and later ones no longer count.
  uint64_t batch_id() const { return batch_id_; }
  std::optional<uint64_t> take_rollback() { return trust_.take_rollback(); }
  void forget_batches_from(uint64_t batch) { trust_.forget_batches_from(batch); }

  // Workers silent for liveness_ms are removed (their jobs re-queued, counted as a death for each job).
  std::vector<WorkerId> expire(Millis now);
  // A worker whose connection failed (a send to it failed): removed as dead, and counted as lost.
  void lose_worker(const WorkerId& id);
  // The jobs to send now (each worker filled up to jobs_ahead) and the heartbeats due.
  std::vector<Outgoing> outgoing(Millis now);
  // The same, each handed to `deliver` as soon as it is made, so that the first jobs of a batch are on their way
  // while the rest are made. `deliver` must not call the dispatcher (a send that fails is reported after).
  void outgoing(Millis now, const std::function<void(Outgoing&&)>& deliver);

  // A new batch (the previous one must be done or abandoned). Tasks are copied; θ is shared, not copied.
  void start_batch(std::span<const RolloutTask> tasks);
  void abandon_batch();
  bool batch_done() const { return batch_active_ && results_.remaining() == 0; }
  // The results in task order; ends the batch.
  std::vector<RolloutResult> take_results();
  // The ranges [first, end) of tasks whose results became final since the last call, and those results.
  std::vector<std::pair<size_t, size_t>> take_ready_ranges();
  std::span<const RolloutResult> results(size_t first, size_t end) const { return results_.results(first, end); }
  // Set when a task killed max_attempts proven workers or proven workers refused a task: the run must stop.
  const std::optional<std::string>& failure() const { return failure_; }

  size_t worker_count() const { return workers_.size(); }
  bool has_worker(const WorkerId& id) const { return workers_.contains(id); }
  size_t ready_workers() const { return workers_.ready(); }  // those that may be sent jobs
  int64_t queue_depth() const { return static_cast<int64_t>(jobs_.queued().size()); }
  std::vector<WorkerView> workers() const;  // connected, in the order they said Hello, each with its trust
  DispatchView view(Millis now) const;      // the workers and every counter below, for the status socket
  // Frames and Hellos refused or dropped, by reason's name (drop_reason.h).
  const std::map<std::string, int64_t>& dropped() const { return dropped_; }
  int64_t backup_jobs() const { return jobs_.backups(); }  // jobs sent to a second worker
  int64_t workers_demoted() const { return trust_.demoted(); }
  // Workers refused for a wrong result, with their names and why, in order (the log and /metrics read them).
  const std::vector<Refusal>& wrong_workers() const { return trust_.refusals(); }
  // What trust has recorded: the workers refused, by routing id; for each worker that may still be found wrong, the
  // first batch in which an unchecked answer of its became final; its counters.
  const WorkerTrust& trust() const { return trust_; }
  void count_drop(DropReason reason) { dropped_[name(reason)] += 1; }
  const DispatchSettings& settings() const { return settings_; }

 private:
  // The worker no longer holds the job; a job no one holds any more goes back to the queue. A death counts
  // towards the poison rule only when the worker was proven; otherwise the job is tainted.
  void release(uint64_t job_id, const RegisteredWorker& worker, bool died);
  void requeue(OpenJob& job, bool died);
  void send(OpenJob& job, RegisteredWorker& worker, Millis now, const std::function<void(Outgoing&&)>& deliver);
  // Takes jobs back from workers not proven whose lease ran out, and demotes them.
  void expire_leases(Millis now, bool unproven_holding);
  // What an idle worker may be given beyond the queue, found once per outgoing() rather than once per worker:
  // jobs held by workers not proven (taken at once by proven ones), and jobs held past the lease (backed up).
  struct Spare {
    bool unproven_holding = false;  // some worker not proven holds a job
    bool overdue = false;           // some open job may be backed up: every holder has held it past the lease
  };
  // The queued job the worker may take, or a job to back up on it; nullptr when none. Reads spare_.
  OpenJob* next_job(const RegisteredWorker& worker, Millis now);
  bool may_take(const OpenJob& job, const RegisteredWorker& worker) const;  // trust's answer, with the holders'
  bool proven_can_take(const OpenJob& job) const;                           // a ready proven worker may take it
  // A Result for a job the worker does not hold: dropped, though a late one that parses still proves the worker.
  void on_unexpected_result(RegisteredWorker* worker, const wire::Result& result);
  // An error Result: the job goes back, and the run stops only when proven workers agree.
  void on_error(RegisteredWorker& worker, OpenJob& job, const std::string& error);
  // A valid answer: taken, held for a check, compared, or deciding between two.
  void on_answer(RegisteredWorker& worker, OpenJob& job, std::vector<RolloutResult> results);
  // What a settlement says of workers: those found wrong refused, the others credited with a check.
  void apply_checks(const Settlement& settlement);
  // The settled results taken: the job ends, and its other holders' answers, when they come, are late.
  void accept(OpenJob& job, Settlement&& settlement);
  // The answer of a holder beaten to job [begin, end) by another, come while the batch runs: judged against the
  // results taken, as a second answer is (so a newcomer whose trial a proven worker finished first is checked all
  // the same); two that differ send the tasks out again for a third answer to decide.
  void compare_late(WorkerId id, size_t begin, size_t end, std::vector<RolloutResult> late);
  // Jobs awaiting an answer to check against that no connected worker can give go to the coordinator
  // (take_coordinator_checks); jobs refused by every proven worker connected stop the run.
  void check_unanswerable(Millis now);
  bool eligible_checker(const OpenJob& job, const RegisteredWorker& worker) const;
  void new_jobs(size_t begin, size_t end, size_t per_job, int deaths, bool front);
  size_t tasks_per_job(size_t tasks) const;  // how a new batch is cut
  std::string describe_task(size_t index) const;

  DispatchSettings settings_;
  WorkerRegistry workers_;  // who is connected, what each holds, trials
  JobQueue jobs_;           // the batch's open jobs, their queue and leases
  WorkerTrust trust_;       // how far each worker is trusted, what answers settle, refusals and rollbacks

  // the batch
  bool batch_active_ = false;
  uint64_t batch_id_ = 0;
  std::vector<RolloutTask> tasks_;
  JobEncoder encoder_;          // the batch's Jobs on the wire: its θs by hash, each encoded once
  BatchResults results_;        // by task: which are in, from whom, which are final
  Spare spare_;                 // of the outgoing() under way
  bool refusals_seen_ = false;  // a proven worker refused a job of this batch

  std::optional<std::string> failure_;
  std::map<std::string, int64_t> dropped_;
  int64_t lost_ = 0;
  std::vector<Outgoing> refusals_;        // Refused messages to send
  std::deque<WorkerView> refused_views_;  // the workers refused, as they were, the latest kMaxRefusedShown
};

}  // namespace poet
