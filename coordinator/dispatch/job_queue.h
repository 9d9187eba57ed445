#pragma once
// The open jobs of a batch and their leases: the queue they wait in (jobs put back go to its front, so a batch
// finishes in the order it was cut), who holds each and since when, how long finished jobs took (the lease: a job
// held longer is backed up, or taken back from a worker not proven), and which job an idle worker may be given
// beyond the queue (a trial, a job held only by workers not proven, a backup). Who may take which job is the
// caller's to say (a predicate); time is a parameter; no workers, no sockets.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"
#include "coordinator/dispatch/running_median.h"
#include "coordinator/trust/job_trust.h"

namespace poet {

struct Lease {
  WorkerId worker;
  Millis since = 0;
};

struct OpenJob {
  uint64_t id = 0;
  size_t begin = 0;  // tasks [begin, end) of the batch
  size_t end = 0;
  int deaths = 0;             // proven workers that died holding it
  std::vector<Lease> leases;  // its holders: none while queued, more once backed up
  bool queued = false;
  const JobTrust* trust = nullptr;   // the referee's record: chosen for a check, failed by whom, the answers it holds
  std::set<WorkerId> missing_theta;  // workers that said they lacked its θ (once each is believed)
  std::set<WorkerId> taken_back;     // not proven, their lease expired: a result that still comes in time is taken

  bool held_by(const WorkerId& worker) const;
  Millis newest_lease() const;  // when its latest holder took it
};

struct JobTimings {
  Millis liveness_ms = 0;       // the lease while no job of the batch has finished
  double backup_factor = 4;     // the lease: this × the median time of the batch's finished jobs (0: never backed up)
  Millis backup_min_ms = 1000;  // and at least this
  int max_leases = 3;           // holders of one job at once: the first and its backups
};

class JobQueue {
 public:
  using Pick = std::function<bool(const OpenJob&)>;  // whether the worker at hand may take the job

  explicit JobQueue(JobTimings timings) : timings_(timings) {}

  void clear();  // a new batch, or none

  // A new job of tasks [begin, end), not queued yet; its id is the next one.
  OpenJob& add(size_t begin, size_t end, int deaths);
  // Jobs queued in this order, at the back of the queue or at its front (keeping their order).
  void enqueue(const std::vector<uint64_t>& ids, bool front);
  void enqueue_front(OpenJob& job);  // put back: first to go out again (nothing when queued already)
  void erase(uint64_t id);           // finished or cut again: out of the queue and forgotten
  void forget_holder(const WorkerId& worker);  // it left: a lease taken back from it no longer takes its result

  OpenJob* find(uint64_t id);
  OpenJob& at(uint64_t id) { return jobs_.at(id); }
  bool contains(uint64_t id) const { return jobs_.contains(id); }
  std::map<uint64_t, OpenJob>& open() { return jobs_; }  // by id
  const std::deque<uint64_t>& queued() const { return queue_; }

  // A result for job `id` from `worker`: the job, when the worker holds it (the lease ends: `took` ms after it
  // began) or held it until its lease was taken back (a result that still comes is taken); nullptr otherwise.
  struct HandIn {
    OpenJob* job = nullptr;
    bool held = false;
    Millis took = 0;
  };
  HandIn hand_in(uint64_t id, const WorkerId& worker, Millis now);
  // The lease held on it by `worker` from now.
  void lease(OpenJob& job, const WorkerId& worker, Millis now) { job.leases.push_back({worker, now}); }
  // A held job finished after `took` ms: the lease follows the batch's median.
  void finished_in(Millis took);
  Millis lease_ms() const { return backup_after_ > 0 ? backup_after_ : timings_.liveness_ms; }

  // Out of the queue: the first queued job `pick` allows, looking at the first few thousand only.
  OpenJob* take_queued(const Pick& pick);
  // Held jobs, not queued: the one with the fewest holders that `pick` allows (a trial), the first whose holders
  // all satisfy `holder_unproven` (taken at once by a proven worker), or a backup: the job whose newest holder
  // took it longest ago, more than a lease ago, with room for another holder (counted).
  OpenJob* fewest_holders(const Pick& pick);
  OpenJob* held_only_by(const std::function<bool(const WorkerId&)>& holder_unproven, const Pick& pick);
  OpenJob* backup(Millis now, const Pick& pick);
  bool any_overdue(Millis now) const;  // some job may be backed up

  // Leases older than the lease whose holder `may_take_back` allows are ended (a result that still comes is taken),
  // and a job no one holds any more goes to the front of the queue. The (job, worker) pairs taken back: what a lease
  // run out means for the job and the worker is trust's to say.
  std::vector<std::pair<uint64_t, WorkerId>> take_back_expired(
      Millis now, const std::function<bool(const WorkerId&)>& may_take_back);

  int64_t backups() const { return backups_; }
  int64_t leases_expired() const { return leases_expired_; }

 private:
  JobTimings timings_;
  std::map<uint64_t, OpenJob> jobs_;  // open jobs by id
  std::deque<uint64_t> queue_;
  uint64_t next_id_ = 1;
  RunningMedian job_times_;  // how long this batch's finished jobs took, from send to result
  Millis backup_after_ = 0;  // the backup time from job_times_ (0: none finished yet)
  int64_t backups_ = 0;
  int64_t leases_expired_ = 0;
};

}  // namespace poet
