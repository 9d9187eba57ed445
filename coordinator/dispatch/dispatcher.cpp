#include "coordinator/dispatch/dispatcher.h"

#include <algorithm>

#include "common/formats/rollout_task_proto.h"
#include "common/text/text_format.h"
#include "coordinator/dispatch/hello_check.h"

namespace poet {

wire::CoordinatorMessage Dispatcher::on_hello(const WorkerId& id, const wire::Hello& hello, Millis now,
                                              const Witness& witness) {
  wire::CoordinatorMessage reply;
  if (trust_.refused(id)) {
    count_drop(DropReason::kWrongWorker);
    reply.mutable_refused()->set_reason("this worker was refused for wrong results");
    return reply;
  }
  if (const std::optional<HelloRefusal> refusal = hello_refusal(hello, settings_.build)) {
    count_drop(refusal->reason);
    reply.mutable_refused()->set_reason(refusal->why);
    return reply;
  }
  if (workers_.contains(id)) remove_worker(id, /*died=*/false);  // said Hello again: a fresh start
  if (workers_.size() >= settings_.max_workers) {
    count_drop(DropReason::kWorkerLimit);
    reply.mutable_refused()->set_reason("the coordinator already has " + std::to_string(workers_.size()) +
                                        " workers, its limit");
    return reply;
  }
  WorkerView view = view_of_hello(id, hello);
  static_cast<Standing&>(view) =
      trust_.newcomer(id, witness, !settings_.local_token.empty() && hello.local_token() == settings_.local_token);
  workers_.add(std::move(view), now);
  reply.mutable_welcome()->set_heartbeat_ms(static_cast<uint32_t>(settings_.heartbeat_ms));
  reply.mutable_welcome()->set_liveness_ms(static_cast<uint32_t>(settings_.liveness_ms));
  return reply;
}

bool Dispatcher::heard_from(const WorkerId& id, Millis now) { return workers_.heard_from(id, now); }

void Dispatcher::remove_worker(const WorkerId& id, bool died) {
  const std::optional<RegisteredWorker> worker = workers_.remove(id);
  if (!worker) return;
  for (auto& [job_id, job] : jobs_.open()) job.taken_back.erase(id);  // a worker of this id is a new one from now on
  // back to the front, in their order, so the batch finishes in the order it was cut
  for (auto job = worker->jobs.rbegin(); job != worker->jobs.rend(); ++job) release(*job, *worker, died);
}

void Dispatcher::lose_worker(const WorkerId& id) {
  if (!workers_.contains(id)) return;
  remove_worker(id, /*died=*/true);
  lost_ += 1;
}

void Dispatcher::release(uint64_t job_id, const RegisteredWorker& worker, bool died) {
  OpenJob* job = jobs_.find(job_id);
  if (job == nullptr) return;
  std::erase_if(job->leases, [&](const Lease& lease) { return lease.worker == worker.view.id; });
  if (died) died = trust_.death_counts(job->trust, worker.view);
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
  jobs_.erase(job.id);
  if (deaths >= settings_.max_attempts) {
    for (size_t t = begin; t < end && !failure_; ++t)
      if (!results_.has(t))
        failure_ = describe_task(t) + " was running on " + std::to_string(deaths) +
                   " workers when they died; the run stops rather than lose more workers to it";
    return;
  }
  new_jobs(begin, end, 1, deaths, /*front=*/true);
}

// Jobs of tasks [begin, end) without a result, per_job tasks at most, at the back of the queue or its front.
void Dispatcher::new_jobs(size_t begin, size_t end, size_t per_job, int deaths, bool front) {
  std::vector<uint64_t> made;
  for (size_t t = begin; t < end;) {
    if (results_.has(t)) {
      ++t;
      continue;
    }
    size_t stop = t + 1;
    while (stop < end && stop - t < per_job && !results_.has(stop)) ++stop;
    made.push_back(jobs_.add(t, stop, deaths, trust_.new_job(batch_id_, t, stop)).id);
    t = stop;
  }
  jobs_.enqueue(made, front);
}

void Dispatcher::on_result(const WorkerId& id, const wire::Result& result, Millis now) {
  RegisteredWorker* const worker = workers_.find(id);
  OpenJob* const job = jobs_.find(result.job_id());
  const auto lease = job == nullptr ? std::vector<Lease>::iterator{}
                                    : std::find_if(job->leases.begin(), job->leases.end(),
                                                   [&](const Lease& l) { return l.worker == id; });
  const bool holds = job != nullptr && lease != job->leases.end();
  const bool taken_back = worker != nullptr && job != nullptr && job->taken_back.erase(id) > 0;
  if (worker == nullptr || job == nullptr || (!holds && !taken_back)) {
    on_unexpected_result(worker, result);
    return;
  }
  worker->trial_since.reset();  // it answered a job it held, rightly or not
  RegisteredWorker& w = *worker;
  OpenJob& j = *job;
  const Millis took = holds ? now - lease->since : 0;
  if (holds) j.leases.erase(lease);
  w.view.last_heard = now;
  w.jobs.erase(j.id);
  if (result.has_error()) {
    // the worker dropped θs it was sent: send them again; the job comes with them, so a second time is an error
    if (result.missing_theta() && j.missing_theta.insert(id).second) {
      w.thetas_sent.clear();
      if (j.leases.empty()) requeue(j, false);
      return;
    }
    on_error(w, j, result.error());
    return;
  }
  std::optional<std::vector<RolloutResult>> parsed = results_from_wire(result, j.end - j.begin);
  if (!parsed) {  // a worker that sends nonsense is treated as one that died with the job
    count_drop(DropReason::kBadResult);
    if (!w.view.proven) trust_.demote(w.view);
    j.leases.push_back({id, now});  // released below as by a death
    release(j.id, w, /*died=*/true);
    return;
  }
  trust_.answered(w.view, /*counted=*/true);  // alive and answering; whether it computes right is probation's to say
  w.view.jobs_done += 1;
  w.view.results_done += static_cast<int64_t>(parsed->size());
  if (holds) jobs_.finished_in(took);  // a result taken back from an expired lease says nothing of job times
  on_answer(w, j, std::move(*parsed));
}

void Dispatcher::on_unexpected_result(RegisteredWorker* worker, const wire::Result& result) {
  // a job its backup finished first; or a stranger, or a job this worker no longer holds (re-queued, or done)
  std::optional<std::pair<size_t, size_t>> beaten;
  if (worker != nullptr) {
    if (const auto it = worker->beaten.find(result.job_id()); it != worker->beaten.end()) {
      beaten = it->second;
      worker->beaten.erase(it);
    }
  }
  count_drop(beaten ? DropReason::kLateResult : DropReason::kUnexpectedResult);
  // the answer to its trial, come after its batch ended
  const bool trial = worker != nullptr && worker->trial_since && worker->trial_job == result.job_id();
  if (!beaten && !trial) return;
  // a late answer still shows the worker alive and answering when it parses (a new worker beaten at every batch's
  // tail by proven ones would otherwise never be proven, and one whose trial outlived its batch would be demoted)
  worker->trial_since.reset();
  std::optional<std::vector<RolloutResult>> late;
  if (!result.has_error() && result.results_size() > 0) late = results_from_wire(result, result.results_size());
  if (late) trust_.answered(worker->view, /*counted=*/false);
  if (beaten && late) {  // last: it may refuse the worker
    compare_late(worker->view.id, beaten->first, beaten->second, std::move(*late));
  }
}

void Dispatcher::compare_late(const WorkerId id, size_t begin, size_t end, std::vector<RolloutResult> late) {
  if (!trust_.verifies() || !batch_active_ || batch_done() || late.size() != end - begin) return;
  // the results taken must still be one answer's, whole: not redone since, in other jobs
  const WorkerId taken_from = results_.from(begin);
  const bool taken_final = results_.is_final(begin);
  for (size_t t = begin; t < end; ++t)
    if (!results_.has(t) || results_.from(t) != taken_from || results_.is_final(t) != taken_final) return;
  const RegisteredWorker* worker = workers_.find(id);
  if (worker == nullptr) return;
  const std::span<const RolloutResult> taken = results_.results(begin, end);
  Settlement settlement = trust_.late_answer(trust_.taken_answer(taken_from, {taken.begin(), taken.end()}), taken_final,
                                             trust_.answer_of(id, worker->view, std::move(late)), worker->view.local);
  if (settlement.kind == Settlement::Kind::kReopen) {  // two answers that differ: a third decides
    results_.reopen(begin, end);
    OpenJob& job = jobs_.add(begin, end, 0, trust_.new_job(batch_id_, begin, end));
    job.trust.answers = std::move(settlement.reopened);
    jobs_.enqueue_front(job);
    return;
  }
  if (settlement.checked_since)
    if (RegisteredWorker* taken_worker = workers_.find(*settlement.checked_since))
      trust_.checked_since(taken_worker->view);
  // the taken answer found wrong: its results not final are withdrawn and computed again (refuse)
  apply_checks(settlement);
}

void Dispatcher::on_error(RegisteredWorker& worker, OpenJob& job, const std::string& error) {
  switch (trust_.error(job.trust, worker.view.id, worker.view, workers_.proven())) {
    case ErrorVerdict::kFromUnproven:
      count_drop(DropReason::kErrorFromUnproven);
      break;
    case ErrorVerdict::kRetry:  // another proven worker says whether the error is real
      refusals_seen_ = true;
      break;
    case ErrorVerdict::kStop: {
      refusals_seen_ = true;
      const size_t refusing = job.trust.refusing.size();
      if (!failure_)
        failure_ = "worker " + worker.view.name + " refused " + describe_task(job.begin) +
                   (job.end - job.begin > 1 ? " (or a later task of its job)" : "") + ": " + error +
                   (refusing > 1 ? " (and so did " + std::to_string(refusing - 1) + " other worker" +
                                       (refusing > 2 ? "s" : "") + ")"
                                 : "");
      return;
    }
  }
  if (job.leases.empty()) requeue(job, false);
}

void Dispatcher::on_answer(RegisteredWorker& worker, OpenJob& job, std::vector<RolloutResult> results) {
  Settlement settlement = trust_.answer(job.trust, worker.view.id, worker.view, std::move(results), batch_id_);
  switch (settlement.kind) {
    case Settlement::Kind::kHold:
      if (job.leases.empty()) jobs_.enqueue_front(job);  // for a second worker, or a third to decide
      return;
    case Settlement::Kind::kCoordinator:  // three answers and none confirmed: not sent out again
      trust_.ask_coordinator(job.id, job.trust);
      return;
    default:
      apply_checks(settlement);
      accept(job, std::move(settlement));  // ends the job
      return;
  }
}

void Dispatcher::apply_checks(const Settlement& settlement) {
  for (const WorkerId& id : settlement.passed)
    if (RegisteredWorker* passed = workers_.find(id)) trust_.passed_check(passed->view);
  // refused before the results are taken: theirs held back must not become final with this job, which may be the
  // batch's last
  for (const WorkerId& id : settlement.wrong) refuse(id, settlement.why_wrong);
}

void Dispatcher::accept(OpenJob& job, Settlement&& settlement) {
  if (RegisteredWorker* credited = workers_.find(settlement.credited)) {
    trust_.took_answer(credited->view, settlement.checked);
    trust_.credit(settlement.credited, credited->view.witness);
  }
  results_.put(job.begin, settlement.results, settlement.credited, settlement.final_now);
  for (const Lease& other : job.leases) {  // the other holders' results, when they come, are late
    RegisteredWorker* holder = workers_.find(other.worker);
    if (holder == nullptr) continue;
    holder->jobs.erase(job.id);
    holder->beaten[job.id] = {job.begin, job.end};
  }
  jobs_.erase(job.id);
}

void Dispatcher::refuse(const WorkerId id, const std::string& why) {
  const RegisteredWorker* worker = workers_.find(id);
  if (!trust_.refuse(id, {worker != nullptr ? worker->view.name : peer_id_text(id), why}, batch_id_)) return;
  if (worker != nullptr) {
    WorkerView shown = worker->view;
    shown.trust = Trust::kRefused;
    shown.jobs_held = 0;
    refused_views_.push_back(std::move(shown));
    if (refused_views_.size() > kMaxRefusedShown) refused_views_.pop_front();
  }
  // its answers awaiting a check, and those of its key's other connections (gone ones too), are worth nothing: those
  // jobs wait for answers from others
  const Witness witness = worker != nullptr && !worker->view.witness.empty() ? worker->view.witness : id;
  for (auto& [job_id, job] : jobs_.open())
    if (trust_.forget_answers_of(job.trust, id, witness) && job.leases.empty()) jobs_.enqueue_front(job);
  if (worker != nullptr) {
    Outgoing refusal{id, {}};
    refusal.message.mutable_refused()->set_reason("this worker " + why);
    refusals_.push_back(std::move(refusal));
    remove_worker(id, /*died=*/false);
  }
  // every result of the batch taken from it is computed again, by others
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
      trust_.lease_ran_out(jobs_.at(job_id).trust, id, holder.view);
    }
  }
  // a job it held ended with its batch, unanswered, and the lease has run out since
  for (RegisteredWorker* worker : workers_.in_order())
    trust_.trial_ran_out(worker->view, worker->trial_since, !worker->jobs.empty(), now, jobs_.lease_ms());
}

bool Dispatcher::proven_can_take(const OpenJob& job) const {
  return std::any_of(workers_.in_order().begin(), workers_.in_order().end(),
                     [&](const RegisteredWorker* w) { return w->ready && w->view.proven && may_take(job, *w); });
}

bool Dispatcher::may_take(const OpenJob& job, const RegisteredWorker& worker) const {
  if (job.held_by(worker.view.id)) return false;
  switch (trust_.may_take(job.trust, worker.view.id, worker.view)) {
    case Eligibility::kNo:
      return false;
    case Eligibility::kYes:
      return true;
    case Eligibility::kIfNoProvenCan:
      return !proven_can_take(job);
  }
  return false;
}

OpenJob* Dispatcher::next_job(const RegisteredWorker& worker, Millis now) {
  const auto may = [&](const OpenJob& job) { return may_take(job, worker); };
  if (OpenJob* queued = jobs_.take_queued(may)) return queued;
  // Nothing queued: a worker not proven is sent a copy of an open job, the one with the fewest holders, as its
  // trial, so that however many silent peers joined first and took the batch's jobs, the real workers among the
  // new ones get one too and prove themselves within a job's time (each peer holds one trial at a time, and is
  // demoted when it lets one run past its lease).
  if (!worker.view.proven) return jobs_.fewest_holders(may);
  // Nothing queued: a proven worker takes at once a job held only by workers not proven, since those may never
  // answer; so peers that take jobs and sit on them delay nothing while a proven worker is free.
  if (spare_.unproven_holding) {
    if (OpenJob* job = jobs_.held_only_by(workers_.not_proven(), may)) return job;
  }
  // a backup: a job whose every holder has held it past the lease (proven ones: slow, or silent)
  return spare_.overdue ? jobs_.backup(now, may) : nullptr;
}

bool Dispatcher::eligible_checker(const OpenJob& job, const RegisteredWorker& worker) const {
  return worker.ready && !worker.view.demoted && may_take(job, worker);  // may_take: proven workers only
}

void Dispatcher::check_unanswerable(Millis now) {
  if (refusals_seen_) {  // (otherwise no queued job has been refused: none to look at)
    for (const uint64_t id : jobs_.queued()) {
      const OpenJob& job = jobs_.at(id);
      // proven workers that refused it may now be all there are (the others left): the error rule says again
      if (trust_.refused_by_enough(job.trust, workers_.proven()) && !failure_)
        failure_ = "workers refused " + describe_task(job.begin) + " (" + std::to_string(job.trust.refusing.size()) +
                   " of the " + std::to_string(workers_.proven()) + " proven workers connected)";
    }
  }
  if (!trust_.verifies()) return;  // answers are held only to be checked
  const Millis lease = jobs_.lease_ms();
  const auto& connected = workers_.in_order();
  for (auto& [id, job] : jobs_.open()) {
    if (job.trust.answers.empty()) continue;
    const bool checker = job.queued && std::any_of(connected.begin(), connected.end(), [&](const RegisteredWorker* w) {
                           return eligible_checker(job, *w);
                         });
    trust_.coordinator_must_check(id, job.trust, job.queued, checker, job.newest_lease(), now, lease);
  }
}

std::vector<Dispatcher::CoordinatorCheck> Dispatcher::take_coordinator_checks() {
  std::vector<CoordinatorCheck> out;
  for (const uint64_t id : trust_.take_coordinator_jobs()) {
    const OpenJob* job = jobs_.find(id);
    if (!batch_active_ || job == nullptr) continue;
    const std::vector<Answer>& held = job->trust.answers;
    const bool disputed = std::any_of(held.begin(), held.end(),
                                      [&](const Answer& a) { return !same_results(a.results, held[0].results); });
    out.push_back({batch_id_, id, disputed,
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
  OpenJob* job = jobs_.find(job_id);
  if (job == nullptr) return;  // a worker's answer settled it first
  if (results.size() != job->end - job->begin) return;
  Settlement settlement = trust_.coordinator_answer(job->trust, results);
  apply_checks(settlement);
  accept(*job, std::move(settlement));  // ends the job
}

void Dispatcher::send(OpenJob& job, RegisteredWorker& worker, Millis now,
                      const std::function<void(Outgoing&&)>& deliver) {
  const WorkerId& id = worker.view.id;
  jobs_.lease(job, id, now);
  workers_.sent_job(worker, job.id, now);
  if (!worker.view.proven) spare_.unproven_holding = true;
  deliver(encoder_.job(id, job.id, job.begin, job.end, worker.thetas_sent));
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
    spare_ = {unproven_holding, jobs_.any_overdue(now)};
  }
  // One job per worker per pass, so a batch spreads over every worker before any gets a second. But with queued
  // jobs enough to fill every worker, a worker's free places are filled at once, with consecutive jobs: these
  // mostly share a θ, and θ is most of a job's bytes.
  const bool fill_at_once =
      batch_active_ && jobs_.queued().size() >= static_cast<size_t>(settings_.jobs_ahead) * workers_.ready();
  for (bool assigned = true; assigned && !failure_ && batch_active_;) {
    assigned = false;
    for (RegisteredWorker* held : workers_.in_order()) {
      RegisteredWorker& worker = *held;
      const size_t room =
          trust_.jobs_at_once(worker.view, worker.trial_since.has_value(), static_cast<size_t>(settings_.jobs_ahead));
      if (!worker.ready || worker.jobs.size() >= room) continue;
      for (size_t places = fill_at_once ? room - worker.jobs.size() : 1; places > 0; --places) {
        OpenJob* job = next_job(worker, now);
        if (job == nullptr) break;
        send(*job, worker, now, deliver);
        assigned = true;
      }
    }
  }
  for (RegisteredWorker* held : workers_.in_order()) {
    if (now - held->last_sent < settings_.heartbeat_ms) continue;
    Outgoing beat{held->view.id, {}};
    beat.message.mutable_heartbeat();
    deliver(std::move(beat));
    held->last_sent = now;
  }
}

void Dispatcher::start_batch(std::span<const RolloutTask> tasks) {
  abandon_batch();
  batch_active_ = true;
  batch_id_ += 1;
  // a worker gone, with no answer held any more, can no longer be found wrong
  trust_.start_batch([&](const WorkerId& id) { return !workers_.contains(id); });
  tasks_.assign(tasks.begin(), tasks.end());
  results_.start(tasks.size());
  encoder_.start_batch(tasks_, batch_id_);
  for (RegisteredWorker* worker : workers_.in_order()) worker->thetas_sent.clear();

  new_jobs(0, tasks.size(), tasks_per_job(tasks.size()), 0, /*front=*/false);
}

size_t Dispatcher::tasks_per_job(size_t tasks) const {
  size_t threads = 0, workers = 0;
  for (const RegisteredWorker* worker : workers_.in_order()) {
    if (!worker->ready || worker->view.demoted) continue;
    threads += static_cast<size_t>(worker->view.threads);
    workers += 1;
  }
  const auto ceil_div = [](size_t a, size_t b) { return (a + b - 1) / b; };
  // About four jobs per thread of the workers present, so that a slow or lost worker delays little. But a batch
  // that goes out whole at once (jobs_ahead jobs a worker) is not balanced by its queue: there, one job a worker
  // ends no later and costs the coordinator half the messages or fewer.
  size_t per_job = ceil_div(tasks, 4 * std::max<size_t>(threads, 1));
  if (workers > 0 && ceil_div(tasks, per_job) <= static_cast<size_t>(settings_.jobs_ahead) * workers)
    per_job = ceil_div(tasks, workers);
  return std::clamp<size_t>(per_job, 1, static_cast<size_t>(settings_.max_chunk));
}

void Dispatcher::abandon_batch() {
  for (RegisteredWorker* worker : workers_.in_order()) {  // their late results will be dropped
    worker->jobs.clear();
    worker->beaten.clear();
  }
  refusals_seen_ = false;
  trust_.end_batch();
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

std::vector<std::pair<size_t, size_t>> Dispatcher::take_ready_ranges() {
  return results_.take_ready_ranges(batch_done());
}

DispatchView Dispatcher::view(Millis now) const {
  DispatchView v;
  v.workers = workers();
  v.refused.assign(refused_views_.begin(), refused_views_.end());
  v.at = now;
  v.ready_workers = ready_workers();
  v.queue_depth = queue_depth();
  v.in_flight_jobs = workers_.jobs_held();
  v.dropped_frames = dropped_;
  v.workers_joined = workers_.joined();
  v.workers_lost = lost_;
  v.backup_jobs = backup_jobs();
  v.leases_expired = jobs_.leases_expired();
  v.workers_demoted = workers_demoted();
  v.verified_jobs = trust_.verified();
  v.wrong_workers = static_cast<int64_t>(trust_.refusals().size());
  v.coordinator_checks = trust_.coordinator_checks();
  v.rollbacks = trust_.rollbacks();
  return v;
}

std::vector<WorkerView> Dispatcher::workers() const {
  std::vector<WorkerView> views = workers_.views();
  for (WorkerView& view : views) view.trust = trust_.level(view);
  return views;
}

std::string Dispatcher::describe_task(size_t index) const {
  const RolloutTask& task = tasks_.at(index);
  std::string text = "task " + std::to_string(index) + " of the batch (course " + task.env.encoding.name + " seed " +
                     std::to_string(task.env.seed) + ", θ " + hex_text(encoder_.theta_hash_of(index));
  if (task.perturbation)
    text += ", perturbation " + hex_text(task.perturbation->key) + " sign " + std::to_string(task.perturbation->sign);
  return text + ")";
}

}  // namespace poet
