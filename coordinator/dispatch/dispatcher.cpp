#include "coordinator/dispatch/dispatcher.h"

#include <algorithm>

#include "common/formats/rollout_task_proto.h"
#include "coordinator/dispatch/batch_cut.h"
#include "coordinator/dispatch/hello_check.h"
#include "coordinator/dispatch/run_failure.h"

namespace poet {

wire::CoordinatorMessage Dispatcher::on_hello(const WorkerId& id, const wire::Hello& hello, Millis now,
                                              const std::string& key) {
  wire::CoordinatorMessage reply;
  const auto refused = [&](DropReason reason, const std::string& why) {
    count_drop(reason);
    reply.mutable_refused()->set_reason(why);
    return reply;
  };
  if (const std::optional<std::string> why = referee_.hello_refused(id, key))
    return refused(DropReason::kWrongWorker, *why);
  if (const std::optional<HelloRefusal> refusal = hello_refusal(hello, settings_.build))
    return refused(refusal->reason, refusal->why);
  if (workers_.contains(id)) remove_worker(id, /*died=*/false);  // said Hello again: a fresh start
  if (workers_.size() >= settings_.max_workers)
    return refused(DropReason::kWorkerLimit,
                   "the coordinator already has " + std::to_string(workers_.size()) + " workers, its limit");
  WorkerFacts facts = facts_of_hello(id, hello);
  const bool local = !settings_.local_token.empty() && hello.local_token() == settings_.local_token;
  const Standing& standing = referee_.joined(id, facts.name, key, local);
  workers_.add(std::move(facts), standing, now);
  reply.mutable_welcome()->set_heartbeat_ms(static_cast<uint32_t>(settings_.heartbeat_ms));
  reply.mutable_welcome()->set_liveness_ms(static_cast<uint32_t>(settings_.liveness_ms));
  return reply;
}

void Dispatcher::remove_worker(const WorkerId& id, bool died, bool refused) {
  const std::optional<RegisteredWorker> worker = workers_.remove(id, refused);
  if (!worker) return;
  jobs_.forget_holder(id);  // a worker of this id is a new one from now on
  // back to the front, in their order, so the batch finishes in the order it was cut
  for (auto job = worker->jobs.rbegin(); job != worker->jobs.rend(); ++job) release(*job, *worker, died);
  referee_.left(id);
}

void Dispatcher::lose_worker(const WorkerId& id) {
  if (!workers_.contains(id)) return;
  remove_worker(id, /*died=*/true);
  lost_ += 1;
}

void Dispatcher::release(uint64_t job_id, const RegisteredWorker& worker, bool died) {
  OpenJob* job = jobs_.find(job_id);
  if (job == nullptr) return;
  std::erase_if(job->leases, [&](const Lease& lease) { return lease.worker == worker.facts.id; });
  if (died) died = referee_.died_with(job_id, *worker.standing);
  // a backed-up job still held by its other worker stays with it: that worker's result will do
  if (job->leases.empty()) requeue(*job, died);
}

void Dispatcher::requeue(OpenJob& job, bool died) {
  if (!died) {
    jobs_.enqueue_front(job);
    return;
  }
  // A job whose worker died may hold a task that kills workers: it is retried one task per job, so the task
  // that does is found and named.
  const int deaths = job.deaths + 1;
  const size_t begin = job.begin;
  const size_t end = job.end;
  close_job(job.id);
  if (deaths >= settings_.max_attempts) {
    const std::vector<BatchResults::Range> unanswered = results_.missing(begin, end, 1);
    if (!unanswered.empty() && !failure_) failure_ = killed_workers(encoder_.describe(unanswered[0].first), deaths);
    return;
  }
  new_jobs(begin, end, 1, deaths, /*front=*/true);
}

OpenJob& Dispatcher::open_job(size_t begin, size_t end, int deaths, std::vector<Answer> held) {
  OpenJob& job = jobs_.add(begin, end, deaths);
  job.trust = &referee_.opened(job.id, batch_id_, begin, end, std::move(held));
  return job;
}

void Dispatcher::close_job(uint64_t job_id) {
  jobs_.erase(job_id);
  referee_.closed(job_id);
}

// Jobs of tasks [begin, end) without a result, per_job tasks at most, at the back of the queue or its front.
void Dispatcher::new_jobs(size_t begin, size_t end, size_t per_job, int deaths, bool front) {
  std::vector<uint64_t> made;
  for (const auto& [first, stop] : results_.missing(begin, end, per_job))
    made.push_back(open_job(first, stop, deaths).id);
  jobs_.enqueue(made, front);
}

void Dispatcher::on_result(const WorkerId& id, const wire::Result& result, Millis now) {
  RegisteredWorker* const worker = workers_.find(id);
  const JobQueue::HandIn in = worker == nullptr ? JobQueue::HandIn{} : jobs_.hand_in(result.job_id(), id, now);
  if (in.job == nullptr) {
    on_unexpected_result(worker, result);
    return;
  }
  RegisteredWorker& w = *worker;
  OpenJob& j = *in.job;
  w.trial_since.reset();  // it answered a job it held, rightly or not
  w.facts.last_heard = now;
  w.jobs.erase(j.id);
  if (result.has_error()) {
    // the worker dropped θs it was sent: send them again; the job comes with them, so a second time is an error
    if (result.missing_theta() && j.missing_theta.insert(id).second) {
      w.thetas_sent.clear();
      if (j.leases.empty()) requeue(j, false);
      return;
    }
    Effects effects = referee_.error(j.id, *w.standing);
    if (effects.error == ErrorVerdict::kStop && !failure_)
      failure_ = refused_by_worker(w.facts.name, encoder_.describe(j.begin), j.end - j.begin > 1, result.error(),
                                   referee_.job(j.id).refusing.size());
    apply(std::move(effects));
    return;
  }
  std::optional<std::vector<RolloutResult>> parsed = results_from_wire(result, j.end - j.begin);
  if (!parsed) {  // a worker that sends nonsense is treated as one that died with the job
    count_drop(DropReason::kBadResult);
    referee_.sent_nonsense(*w.standing);
    j.leases.push_back({id, now});  // released below as by a death
    release(j.id, w, /*died=*/true);
    return;
  }
  w.facts.jobs_done += 1;
  w.facts.results_done += static_cast<int64_t>(parsed->size());
  if (in.held) jobs_.finished_in(in.took);  // a result taken back from an expired lease says nothing of job times
  apply(referee_.answer(j.id, *w.standing, std::move(*parsed), batch_id_), &j);
}

void Dispatcher::on_unexpected_result(RegisteredWorker* worker, const wire::Result& result) {
  // a job its backup finished first; or a stranger, or a job this worker no longer holds (re-queued, or done)
  const std::optional<std::pair<size_t, size_t>> beaten =
      worker != nullptr ? worker->take_beaten(result.job_id()) : std::nullopt;
  count_drop(beaten ? DropReason::kLateResult : DropReason::kUnexpectedResult);
  // the answer to its trial, come after its batch ended
  const bool trial = worker != nullptr && worker->trial_since && worker->trial_job == result.job_id();
  if (!beaten && !trial) return;
  // a late answer still shows the worker alive and answering when it parses (a new worker beaten at every batch's
  // tail by proven ones would otherwise never be proven, and one whose trial outlived its batch would be demoted)
  worker->trial_since.reset();
  std::optional<std::vector<RolloutResult>> late;
  if (!result.has_error() && result.results_size() > 0) late = results_from_wire(result, result.results_size());
  if (!late) return;
  referee_.answered_late(worker->facts.id);
  if (beaten) compare_late(worker->facts.id, beaten->first, beaten->second, std::move(*late));  // may refuse it
}

void Dispatcher::compare_late(const WorkerId& id, size_t begin, size_t end, std::vector<RolloutResult> late) {
  if (!referee_.verifies() || !batch_active_ || batch_done() || late.size() != end - begin) return;
  const std::optional<BatchResults::Answer> taken = results_.one_answer(begin, end);
  if (!taken) return;  // the results taken were redone since, in other jobs
  apply(referee_.late_answer(id, std::move(late), taken->from, results_.results(begin, end), taken->final, begin, end,
                             batch_id_));
}

void Dispatcher::apply(Effects&& effects, OpenJob* event_job) {
  for (const uint64_t id : effects.requeue)
    if (OpenJob* job = jobs_.find(id); job != nullptr && job->leases.empty()) jobs_.enqueue_front(*job);
  for (const Effects::Refuse& refused : effects.refuse) refuse(refused.worker, refused.why);
  for (std::string& key : effects.refuse_keys) refused_keys_.push_back(std::move(key));
  if (effects.take) take(std::move(*effects.take), event_job);
  if (effects.reopen) {  // two answers that differ: a third decides
    results_.reopen(effects.reopen->begin, effects.reopen->end);
    jobs_.enqueue_front(open_job(effects.reopen->begin, effects.reopen->end, 0, std::move(effects.reopen->held)));
  }
  to_coordinator_.insert(to_coordinator_.end(), effects.to_coordinator.begin(), effects.to_coordinator.end());
  if (effects.error == ErrorVerdict::kFromUnproven) count_drop(DropReason::kErrorFromUnproven);
  if (effects.error == ErrorVerdict::kRetry || effects.error == ErrorVerdict::kStop) refusals_seen_ = true;
}

void Dispatcher::take(Effects::Take&& take, OpenJob* event_job) {
  OpenJob* job = event_job != nullptr && event_job->id == take.job ? event_job : jobs_.find(take.job);
  if (job == nullptr) return;
  results_.put(job->begin, take.results, take.credited, take.final_now);
  for (const Lease& other : job->leases) {  // the other holders' results, when they come, are late
    RegisteredWorker* holder = workers_.find(other.worker);
    if (holder == nullptr) continue;
    holder->jobs.erase(job->id);
    holder->beaten[job->id] = {job->begin, job->end};
  }
  close_job(job->id);
}

void Dispatcher::refuse(const WorkerId& id, const std::string& why) {
  if (workers_.contains(id)) {
    refusals_.push_back(refusal_to(id, "this worker " + why));
    remove_worker(id, /*died=*/false, /*refused=*/true);
  }
  // every result of the batch taken from it is computed again, by others (gone or not)
  // (those reported final were checked by another worker, or came from a local one: they stand)
  for (const auto& [first, end] : results_.withdraw(id))
    new_jobs(first, end, static_cast<size_t>(settings_.max_chunk), 0, /*front=*/true);
}

std::vector<WorkerId> Dispatcher::expire(Millis now) {
  std::vector<WorkerId> dead = workers_.silent(now, settings_.liveness_ms);
  for (const WorkerId& id : dead) lose_worker(id);
  return dead;
}

void Dispatcher::expire_leases(Millis now, bool unproven_holding) {
  // leases of proven workers never expire (they are backed up): with none held by others, no job need be looked at
  if (unproven_holding) {
    for (const auto& [job_id, id] : jobs_.take_back_expired(now, workers_.not_proven())) {
      RegisteredWorker& holder = *workers_.find(id);
      holder.jobs.erase(job_id);
      referee_.lease_ran_out(job_id, *holder.standing);
    }
  }
  // a job it held ended with its batch, unanswered, and the lease has run out since
  for (RegisteredWorker* worker : workers_.in_order())
    if (worker->trial_since && !worker->standing->proven)
      referee_.trial_ran_out(*worker->standing, worker->trial_since, !worker->jobs.empty(), now, jobs_.lease_ms());
}

void Dispatcher::check_unanswerable(Millis now) {
  if (refusals_seen_) {  // (otherwise no queued job has been refused: none to look at)
    for (const uint64_t id : jobs_.queued()) {
      const OpenJob& job = jobs_.at(id);
      // proven workers that refused it may now be all there are (the others left): the error rule says again
      if (referee_.refused_by_enough(id) && !failure_)
        failure_ = refused_by_workers(encoder_.describe(job.begin), job.trust->refusing.size(), workers_.proven());
    }
  }
  if (!referee_.verifies()) return;  // answers are held only to be checked
  for (auto& [id, job] : jobs_.open()) {
    if (job.trust->answers.empty()) continue;
    const bool checker = job.queued && assignment_.checker_connected(job);
    apply(referee_.stuck(id, job.queued, checker, job.newest_lease(), now, jobs_.lease_ms()));
  }
}

std::vector<Dispatcher::CoordinatorCheck> Dispatcher::take_coordinator_checks() {
  std::vector<CoordinatorCheck> out;
  for (const uint64_t id : std::exchange(to_coordinator_, {})) {
    const OpenJob* job = jobs_.find(id);
    if (!batch_active_ || job == nullptr) continue;
    out.push_back({batch_id_, id, disputed(job->trust->answers),
                   std::vector<RolloutTask>(tasks_.begin() + static_cast<std::ptrdiff_t>(job->begin),
                                            tasks_.begin() + static_cast<std::ptrdiff_t>(job->end))});
  }
  return out;
}

bool Dispatcher::awaits_coordinator(uint64_t batch_id, uint64_t job_id) const {
  return batch_active_ && batch_id == batch_id_ && jobs_.contains(job_id);
}

void Dispatcher::settle_by_coordinator(uint64_t batch_id, uint64_t job_id, const std::vector<RolloutResult>& results) {
  if (!batch_active_ || batch_id != batch_id_) return;
  const OpenJob* job = jobs_.find(job_id);
  if (job == nullptr || results.size() != job->end - job->begin) return;  // a worker's answer settled it first
  apply(referee_.coordinator_answer(job_id, results, batch_id_));
}

void Dispatcher::send(OpenJob& job, RegisteredWorker& worker, Millis now,
                      const std::function<void(Outgoing&&)>& deliver) {
  jobs_.lease(job, worker.facts.id, now);
  workers_.sent_job(worker, job.id, now);
  deliver(encoder_.job(worker.facts.id, job.id, job.begin, job.end, worker.thetas_sent));
}

std::vector<Outgoing> Dispatcher::outgoing(Millis now) {
  std::vector<Outgoing> out;
  outgoing(now, [&](Outgoing&& message) { out.push_back(std::move(message)); });
  return out;
}

void Dispatcher::outgoing(Millis now, const std::function<void(Outgoing&&)>& deliver) {
  for (Outgoing& refusal : std::exchange(refusals_, {})) deliver(std::move(refusal));
  if (batch_active_) {
    // looked for once a round: a lease taken back below can only make it stale-true, which costs a look, no job
    const bool unproven_holding = workers_.unproven_holding();
    expire_leases(now, unproven_holding);
    check_unanswerable(now);
    if (!failure_)
      assignment_.assign(now, unproven_holding, static_cast<size_t>(settings_.jobs_ahead),
                         [&](OpenJob& job, RegisteredWorker& worker) { send(job, worker, now, deliver); });
  }
  for (const WorkerId& id : workers_.heartbeats_due(now, settings_.heartbeat_ms)) deliver(heartbeat_to(id));
}

void Dispatcher::start_batch(std::span<const RolloutTask> tasks) {
  abandon_batch();
  batch_active_ = true;
  batch_id_ += 1;
  referee_.batch_started();
  tasks_.assign(tasks.begin(), tasks.end());
  results_.start(tasks.size());
  encoder_.start_batch(tasks_, batch_id_);
  const size_t per_job =
      tasks_per_job(tasks.size(), workers_.batch_started(), settings_.jobs_ahead, settings_.max_chunk);
  new_jobs(0, tasks.size(), per_job, 0, /*front=*/false);
}

void Dispatcher::abandon_batch() {
  workers_.batch_ended();  // their late results will be dropped
  refusals_seen_ = false;
  to_coordinator_.clear();
  referee_.batch_ended();
  jobs_.clear();
  tasks_.clear();
  encoder_.clear();
  results_.clear();
  batch_active_ = false;
}

std::vector<RolloutResult> Dispatcher::take_results() {
  std::vector<RolloutResult> out = results_.take();
  abandon_batch();
  return out;
}

DispatchView Dispatcher::view(Millis now) const {
  DispatchView v;
  v.workers = workers();
  v.refused.assign(workers_.refused_views().begin(), workers_.refused_views().end());
  v.at = now;
  v.ready_workers = ready_workers();
  v.queue_depth = static_cast<int64_t>(jobs_.queued().size());
  v.in_flight_jobs = workers_.jobs_held();
  v.dropped_frames = dropped_;
  v.workers_joined = workers_.joined();
  v.workers_lost = lost_;
  v.backup_jobs = backup_jobs();
  v.leases_expired = jobs_.leases_expired();
  v.workers_demoted = referee_.counts().demoted;
  v.verified_jobs = referee_.counts().verified;
  v.wrong_workers = static_cast<int64_t>(referee_.refusals().size());
  v.coordinator_checks = referee_.counts().coordinator_checks;
  v.rollbacks = referee_.counts().rollbacks;
  return v;
}

std::vector<WorkerView> Dispatcher::workers() const {
  std::vector<WorkerView> views = workers_.views();
  for (WorkerView& view : views) view.trust = referee_.level(view);
  return views;
}

}  // namespace poet
