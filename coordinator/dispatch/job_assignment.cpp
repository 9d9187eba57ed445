#include "coordinator/dispatch/job_assignment.h"

#include <algorithm>

namespace poet {

void JobAssignment::assign(Millis now, bool unproven_holding, size_t jobs_ahead,
                           const std::function<void(OpenJob&, RegisteredWorker&)>& send) {
  spare_ = {unproven_holding, jobs_.any_overdue(now)};
  // One job per worker per pass, so a batch spreads over every worker before any gets a second. But with queued
  // jobs enough to fill every worker, a worker's free places are filled at once, with consecutive jobs: these
  // mostly share a θ, and θ is most of a job's bytes.
  const bool fill_at_once = jobs_.queued().size() >= jobs_ahead * workers_.ready();
  for (bool assigned = true; assigned;) {
    assigned = false;
    for (RegisteredWorker* held : workers_.in_order()) {
      RegisteredWorker& worker = *held;
      const size_t room = referee_.jobs_at_once(*worker.standing, worker.trial_since.has_value(), jobs_ahead);
      if (!worker.ready || worker.jobs.size() >= room) continue;
      for (size_t places = fill_at_once ? room - worker.jobs.size() : 1; places > 0; --places) {
        OpenJob* job = next_job(worker, now);
        if (job == nullptr) break;
        send(*job, worker);
        if (!worker.standing->proven) spare_.unproven_holding = true;
        assigned = true;
      }
    }
  }
}

bool JobAssignment::may_take(const OpenJob& job, const RegisteredWorker& worker) const {
  if (job.held_by(worker.facts.id)) return false;
  switch (referee_.may_take(*job.trust, worker.facts.id, *worker.standing)) {
    case Eligibility::kNo:
      return false;
    case Eligibility::kYes:
      return true;
    case Eligibility::kIfNoProvenCan:
      return !proven_can_take(job);
  }
  return false;
}

bool JobAssignment::proven_can_take(const OpenJob& job) const {
  return std::any_of(workers_.in_order().begin(), workers_.in_order().end(),
                     [&](const RegisteredWorker* w) { return w->ready && w->standing->proven && may_take(job, *w); });
}

bool JobAssignment::checker_connected(const OpenJob& job) const {
  return std::any_of(workers_.in_order().begin(), workers_.in_order().end(), [&](const RegisteredWorker* w) {
    return w->ready && !w->standing->demoted && may_take(job, *w);  // may_take: proven workers only
  });
}

OpenJob* JobAssignment::next_job(const RegisteredWorker& worker, Millis now) {
  const JobQueue::Pick may = [&](const OpenJob& job) { return may_take(job, worker); };  // made once, used thrice
  if (OpenJob* queued = jobs_.take_queued(may)) return queued;
  // Nothing queued: a worker not proven is sent a copy of an open job, the one with the fewest holders, as its
  // trial, so that however many silent peers joined first and took the batch's jobs, the real workers among the
  // new ones get one too and prove themselves within a job's time (each peer holds one trial at a time, and is
  // demoted when it lets one run past its lease).
  if (!worker.standing->proven) return jobs_.fewest_holders(may);
  // Nothing queued: a proven worker takes at once a job held only by workers not proven, since those may never
  // answer; so peers that take jobs and sit on them delay nothing while a proven worker is free.
  if (spare_.unproven_holding) {
    if (OpenJob* job = jobs_.held_only_by(workers_.not_proven(), may)) return job;
  }
  // a backup: a job whose every holder has held it past the lease (proven ones: slow, or silent)
  return spare_.overdue ? jobs_.backup(now, may) : nullptr;
}

}  // namespace poet
