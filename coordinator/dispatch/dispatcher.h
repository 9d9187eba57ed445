#pragma once
// The scheduling logic of the remote evaluator, without sockets: a batch of rollout tasks cut into jobs, a queue,
// leases held by workers, liveness by heartbeat (the zguide's Paranoid Pirate), re-queueing of the jobs of a dead
// or departed worker, results matched by job id with duplicates and strangers dropped, the poison-job rule, and
// backup jobs. Time is a parameter (milliseconds on any monotonic clock), so tests drive it with a fake clock. Not
// thread-safe: the remote evaluator's socket thread owns it under its lock. It composes the pieces with one job
// each — WorkerRegistry (who is connected, what each holds, trials), JobQueue (the queue, its leases and backups),
// BatchResults (what is final) and JobEncoder (the wire) — with the Referee (coordinator/trust/referee.h), and keeps
// the rules that join them: how a batch is cut, whom a job goes to, the poison-job rule.
//
// Whether an answer is taken, held, compared or found wrong is the referee's to say: every event of verification
// goes to it, and what it returns is carried out in one place (apply). A worker not proven holds one job at a time,
// and so does one on probation. With nothing queued, a proven worker takes at once a job held only by workers not
// proven (a backup; the first result wins), and a worker not proven gets a copy of an open job as its trial (one at a
// time, across batches until it answers: one that lets a trial run past a lease is demoted). So any number of peers
// that say Hello, heartbeat and never answer cannot queue a real worker behind them, and delay a batch by at most
// about one lease (backup_factor × the median time of the batch's finished jobs, at least backup_min_ms, or
// liveness_ms while none has finished), and by nothing once a proven worker is there. A proven worker's job held
// past the lease is also sent to another worker (up to max_leases holders; the first result wins). The run stops on
// a poison job only when max_attempts proven workers died holding it, and on an error when the referee says proven
// workers agree. Jobs the referee sends to the coordinator are handed out by take_coordinator_checks. A worker found
// wrong is refused from then on (Refused, and its Hellos; with CURVE every connection of its key, whose key the
// caller refuses too: take_refused_keys), and every result of the batch taken from it and not yet reported final is
// computed again. Unchecked answers of workers that are not local are reported final (take_ready) only once
// the batch is whole; referee().rollback_asked() names the first batch to compute again when a worker refused had
// unchecked answers made final.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/protocol/wire_timing.h"
#include "coordinator/dispatch/batch_results.h"
#include "coordinator/dispatch/dispatch_view.h"
#include "coordinator/dispatch/drop_reason.h"
#include "coordinator/dispatch/hello_check.h"
#include "coordinator/dispatch/job_assignment.h"
#include "coordinator/dispatch/job_encoder.h"
#include "coordinator/dispatch/job_queue.h"
#include "coordinator/dispatch/outgoing.h"
#include "coordinator/dispatch/worker_registry.h"
#include "coordinator/trust/referee.h"
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
        referee_({settings.verify_fraction, settings.verify_secret, settings.probation_checks}) {}
  // Its parts point at one another (the assignment at the registry and the queue, each worker at its standing).
  Dispatcher(const Dispatcher&) = delete;
  Dispatcher& operator=(const Dispatcher&) = delete;

  // A Hello: the Welcome to send, or a Refused (wrong protocol version or build fingerprint, max_workers reached, or
  // its routing id or key refused for wrong results; counted). A welcomed worker gets jobs once it has sent another
  // message (proof that it listens). `key`: the CURVE key its connection was admitted with (empty without CURVE).
  wire::CoordinatorMessage on_hello(const WorkerId& id, const wire::Hello& hello, Millis now,
                                    const std::string& key = {});
  // A Result from a worker: accepted when the worker holds the job; otherwise counted and dropped.
  void on_result(const WorkerId& id, const wire::Result& result, Millis now);
  // Any message from a known worker proves it alive; false for a stranger (the caller counts and drops it).
  bool heard_from(const WorkerId& id, Millis now) { return workers_.heard_from(id, now); }
  // A worker that left (Goodbye, or its socket is gone): its jobs go back to the front of the queue.
  void remove_worker(const WorkerId& id, bool died) { remove_worker(id, died, /*refused=*/false); }
  // Workers silent for liveness_ms are removed (their jobs re-queued, counted as a death for each job).
  std::vector<WorkerId> expire(Millis now);
  // A worker whose connection failed (a send to it failed): removed as dead, and counted as lost.
  void lose_worker(const WorkerId& id);
  // The jobs to send now (each worker filled up to jobs_ahead), the Refused of workers found wrong, and the
  // heartbeats due; the second form hands each to `deliver` as soon as it is made, so that the first jobs of a batch
  // are on their way while the rest are made (`deliver` must not call the dispatcher: a send that fails is reported
  // after).
  std::vector<Outgoing> outgoing(Millis now);
  void outgoing(Millis now, const std::function<void(Outgoing&&)>& deliver);

  // A job only the coordinator's own computation can settle (the referee's call): its tasks, handed out once.
  struct CoordinatorCheck {
    uint64_t batch_id = 0;
    uint64_t job_id = 0;
    bool disputed = false;  // answers that differ (otherwise answers that no connected witness can check)
    std::vector<RolloutTask> tasks;
  };
  std::vector<CoordinatorCheck> take_coordinator_checks();
  // Whether that job still waits for an answer (a worker's may have settled it since it was handed out).
  bool awaits_coordinator(uint64_t batch_id, uint64_t job_id) const;
  // The coordinator's results for such a job, for the referee to settle it with. Ignored when the job was settled
  // meanwhile or its batch is over.
  void settle_by_coordinator(uint64_t batch_id, uint64_t job_id, const std::vector<RolloutResult>& results);
  // The CURVE keys of workers found wrong since the last call: the caller refuses them at the handshake.
  std::vector<std::string> take_refused_keys() { return std::exchange(refused_keys_, {}); }

  // A new batch (the previous one must be done or abandoned). Tasks are copied; θ is shared, not copied.
  void start_batch(std::span<const RolloutTask> tasks);
  void abandon_batch();
  bool batch_done() const { return batch_active_ && results_.remaining() == 0; }
  uint64_t batch_id() const { return batch_id_; }  // the batch started last (0: none yet)
  // The results in task order; ends the batch.
  std::vector<RolloutResult> take_results();
  // The results that became final since the last call: each range's first task and its results.
  using Ready = BatchResults::Ready;
  std::vector<Ready> take_ready() { return results_.take_ready(batch_done()); }
  // Set when a task killed max_attempts proven workers or proven workers refused a task: the run must stop.
  const std::optional<std::string>& failure() const { return failure_; }
  // The caller went back to the state after `last_batch`, before the batch the referee asked to compute again:
  // answers of later batches no longer count.
  void went_back(uint64_t last_batch) { referee_.went_back(last_batch); }

  // What trust has recorded: refusals, the rollback asked for, what must stay reachable, its counters.
  const Referee& referee() const { return referee_; }
  size_t worker_count() const { return workers_.size(); }
  size_t ready_workers() const { return workers_.ready(); }  // those that may be sent jobs
  std::vector<WorkerView> workers() const;  // connected, in the order they said Hello, each with its trust
  DispatchView view(Millis now) const;      // the workers and every counter, for the status socket
  // A frame or Hello refused or dropped, counted by reason's name (drop_reason.h): how many so far.
  int64_t count_drop(DropReason reason) { return dropped_[name(reason)] += 1; }
  int64_t backup_jobs() const { return jobs_.backups(); }  // jobs sent to a second worker
  const DispatchSettings& settings() const { return settings_; }

 private:
  // What the referee decided, carried out: jobs put back, workers refused, results taken, tasks reopened, jobs for
  // the coordinator, what an error means. `event_job`: the job the event was about, at hand (no effect before the
  // results are taken closes a job: refusals put jobs back or open new ones).
  void apply(Effects&& effects, OpenJob* event_job = nullptr);
  void refuse(const WorkerId& id, const std::string& why);
  void remove_worker(const WorkerId& id, bool died, bool refused);
  void take(Effects::Take&& take, OpenJob* event_job);  // the settled results: the job ends, others' answers come late
  // A job of tasks [begin, end) and the referee's record of it; a job finished or cut again, forgotten by both.
  OpenJob& open_job(size_t begin, size_t end, int deaths, std::vector<Answer> held = {});
  void close_job(uint64_t job_id);
  // The worker no longer holds the job; a job no one holds any more goes back to the queue. A death counts
  // towards the poison rule only when the worker was proven (the referee's to say).
  void release(uint64_t job_id, const RegisteredWorker& worker, bool died);
  void requeue(OpenJob& job, bool died);
  void send(OpenJob& job, RegisteredWorker& worker, Millis now, const std::function<void(Outgoing&&)>& deliver);
  // Takes jobs back from workers not proven whose lease ran out, and tells the referee (it demotes them).
  void expire_leases(Millis now, bool unproven_holding);
  // A Result for a job the worker does not hold: dropped, though a late one that parses still proves the worker,
  // and one beaten to its job by another holder is compared with the results taken.
  void on_unexpected_result(RegisteredWorker* worker, const wire::Result& result);
  void compare_late(const WorkerId& id, size_t begin, size_t end, std::vector<RolloutResult> late);
  // Jobs refused by every proven worker connected stop the run; jobs holding answers that no connected worker can
  // check, or held past the lease, are the referee's to send to the coordinator.
  void check_unanswerable(Millis now);
  void new_jobs(size_t begin, size_t end, size_t per_job, int deaths, bool front);

  DispatchSettings settings_;
  WorkerRegistry workers_;  // who is connected, what each holds, trials
  JobQueue jobs_;           // the batch's open jobs, their queue and leases
  Referee referee_;         // what answers settle, how far each worker is trusted, refusals and rollbacks
  JobAssignment assignment_{workers_, jobs_, referee_};  // whom each job goes to

  // the batch
  bool batch_active_ = false;
  uint64_t batch_id_ = 0;
  std::vector<RolloutTask> tasks_;
  JobEncoder encoder_;          // the batch's Jobs on the wire: its θs by hash, each encoded once
  BatchResults results_;        // by task: which are in, from whom, which are final
  bool refusals_seen_ = false;  // a proven worker refused a job of this batch
  std::vector<uint64_t> to_coordinator_;  // jobs the referee sent to the coordinator, not yet handed out

  std::optional<std::string> failure_;
  std::map<std::string, int64_t> dropped_;
  int64_t lost_ = 0;
  std::vector<Outgoing> refusals_;         // Refused messages to send
  std::vector<std::string> refused_keys_;  // CURVE keys of workers found wrong, not yet taken
};

}  // namespace poet
