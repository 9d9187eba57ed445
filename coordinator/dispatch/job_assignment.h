#pragma once
// Whom each job goes to, a round at a time: every ready worker is given jobs up to what the referee lets it hold —
// from the queue first; with nothing queued, a worker not proven gets a copy of an open job as its trial, and a
// proven one a job held only by workers not proven, or a backup of a job held past the lease. Who may take which
// job is the referee's to say (a tainted job goes to a worker not proven only when no ready proven one may take it);
// this applies it over the registry and the queue. Time is a parameter; no sockets.

#include <cstddef>
#include <functional>

#include "coordinator/dispatch/job_queue.h"
#include "coordinator/dispatch/worker_registry.h"
#include "coordinator/trust/referee.h"

namespace poet {

class JobAssignment {
 public:
  JobAssignment(WorkerRegistry& workers, JobQueue& jobs, const Referee& referee)
      : workers_(workers), jobs_(jobs), referee_(referee) {}

  // One round: jobs for every ready worker up to its room (jobs_ahead, or what the referee allows), each handed to
  // `send` (which leases it). `unproven_holding`: some worker not proven holds a job.
  void assign(Millis now, bool unproven_holding, size_t jobs_ahead,
              const std::function<void(OpenJob&, RegisteredWorker&)>& send);
  bool may_take(const OpenJob& job, const RegisteredWorker& worker) const;
  // Whether a connected worker may check the job's held answers: ready, not demoted, and allowed to take it.
  bool checker_connected(const OpenJob& job) const;

 private:
  // What an idle worker may be given beyond the queue, found once per round rather than once per worker.
  struct Spare {
    bool unproven_holding = false;  // some worker not proven holds a job (taken at once by proven ones)
    bool overdue = false;           // some open job may be backed up: every holder has held it past the lease
  };
  OpenJob* next_job(const RegisteredWorker& worker, Millis now);  // nullptr when none
  bool proven_can_take(const OpenJob& job) const;                 // a ready proven worker may take it

  WorkerRegistry& workers_;
  JobQueue& jobs_;
  const Referee& referee_;
  Spare spare_;  // of the round under way
};

}  // namespace poet
