#include "coordinator/dispatch/dispatcher.h"

#include <algorithm>
#include <bit>

#include "common/rollout_task_proto.h"
#include "common/text_format.h"
#include "simulation/rng.h"

namespace poet {
namespace {

// Bit for bit: every worker of one build computes exactly the same numbers.
bool same_results(const std::vector<RolloutResult>& a, const std::vector<RolloutResult>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::bit_cast<uint64_t>(a[i].total_reward) != std::bit_cast<uint64_t>(b[i].total_reward) ||
        a[i].steps != b[i].steps || a[i].finished != b[i].finished || a[i].fell != b[i].fell)
      return false;
  }
  return true;
}

// The queued jobs a worker looks through for one it may take; the rest wait their turn.
constexpr size_t kQueueScan = 4096;
// Who answered a task the coordinator computed itself: no routing id can equal it (a peer's own id may not start
// with a zero byte, and libzmq's generated ones are five bytes).
const WorkerId kCoordinatorAnswer("\0the coordinator", 16);

}  // namespace

wire::CoordinatorMessage Dispatcher::on_hello(const WorkerId& id, const wire::Hello& hello, Millis now) {
  wire::CoordinatorMessage reply;
  if (ledger_.refused(id)) {
    count_drop(DropReason::kWrongWorker);
    reply.mutable_refused()->set_reason("this worker returned wrong results");
    return reply;
  }
  if (hello.protocol_version() != wire::PROTOCOL_VERSION) {
    count_drop(DropReason::kWrongVersion);
    reply.mutable_refused()->set_reason("protocol version " + std::to_string(hello.protocol_version()) +
                                        ", the coordinator speaks " + std::to_string(wire::PROTOCOL_VERSION));
    return reply;
  }
  if (settings_.fingerprint_digest != 0 && hello.fingerprint_digest() != settings_.fingerprint_digest) {
    count_drop(DropReason::kWrongFingerprint);
    reply.mutable_refused()->set_reason("build fingerprint " + hex_text(hello.fingerprint_digest()) +
                                        " differs from the coordinator's " + hex_text(settings_.fingerprint_digest) +
                                        ": its returns would differ (compare --fingerprint of both binaries)");
    return reply;
  }
  if (workers_.contains(id)) remove_worker(id, /*died=*/false);  // said Hello again: a fresh start
  if (workers_.size() >= settings_.max_workers) {
    count_drop(DropReason::kWorkerLimit);
    reply.mutable_refused()->set_reason("the coordinator already has " + std::to_string(workers_.size()) +
                                        " workers, its limit");
    return reply;
  }
  Worker worker;
  worker.view.id = id;
  worker.view.name = hello.name().substr(0, 200);
  worker.view.threads = static_cast<int>(std::clamp<uint32_t>(hello.threads(), 1, 4096));
  worker.view.fingerprint_digest = hello.fingerprint_digest();
  worker.view.last_heard = now;
  worker.view.local = !settings_.local_token.empty() && hello.local_token() == settings_.local_token;
  worker.view.proven = worker.view.local;
  worker.last_sent = now;
  arrival_.push_back(&workers_.emplace(id, std::move(worker)).first->second);
  joined_ += 1;
  reply.mutable_welcome()->set_heartbeat_ms(static_cast<uint32_t>(settings_.heartbeat_ms));
  reply.mutable_welcome()->set_liveness_ms(static_cast<uint32_t>(settings_.liveness_ms));
  return reply;
}

bool Dispatcher::heard_from(const WorkerId& id, Millis now) {
  const auto it = workers_.find(id);
  if (it == workers_.end()) return false;
  it->second.view.last_heard = now;
  it->second.ready = true;
  return true;
}

void Dispatcher::remove_worker(const WorkerId& id, bool died) {
  const auto it = workers_.find(id);
  if (it == workers_.end()) return;
  std::erase(arrival_, &it->second);
  const Worker worker = std::move(it->second);
  workers_.erase(it);
  for (auto& [job_id, job] : jobs_) job.taken_back.erase(id);  // a worker of this id is a new one from now on
  // back to the front, in their order, so the batch finishes in the order it was cut
  for (auto job = worker.jobs.rbegin(); job != worker.jobs.rend(); ++job) release(*job, worker, died);
}

void Dispatcher::lose_worker(const WorkerId& id) {
  if (!workers_.contains(id)) return;
  remove_worker(id, /*died=*/true);
  lost_ += 1;
}

void Dispatcher::release(uint64_t job_id, const Worker& worker, bool died) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  Job& job = it->second;
  std::erase_if(job.leases, [&](const Lease& lease) { return lease.worker == worker.view.id; });
  if (died && !worker.view.proven) {
    // a peer that never returned a result proves nothing by dying: a proven worker will say whether it kills
    job.tainted = true;
    died = false;
  }
  // a backed-up job still held by its other worker stays with it: that worker's result will do
  if (job.leases.empty()) requeue(job, died);
}

void Dispatcher::enqueue_front(Job& job) {
  if (job.queued) return;
  job.queued = true;
  queue_.push_front(job.id);
}

void Dispatcher::remove_from_queue(uint64_t job_id) {
  if (const auto it = std::find(queue_.begin(), queue_.end(), job_id); it != queue_.end()) queue_.erase(it);
}

void Dispatcher::requeue(Job& job, bool died) {
  if (!died) {
    enqueue_front(job);
    return;
  }
  // A job whose worker died may hold a task that kills workers: it is retried one task per job, so the task
  // that does is found and named.
  const int deaths = job.deaths + 1;
  const size_t begin = job.begin;
  const size_t end = job.end;
  remove_from_queue(job.id);
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
    Job job;
    job.id = next_job_id_++;
    job.begin = t;
    job.end = stop;
    job.deaths = deaths;
    job.verify = chosen_for_check(job);
    job.queued = true;
    jobs_.emplace(job.id, std::move(job));
    made.push_back(next_job_id_ - 1);
    t = stop;
  }
  if (front) {
    for (auto id = made.rbegin(); id != made.rend(); ++id) queue_.push_front(*id);
  } else {
    queue_.insert(queue_.end(), made.begin(), made.end());
  }
}

bool Dispatcher::chosen_for_check(const Job& job) const {
  if (settings_.verify_fraction <= 0) return false;
  const uint64_t key = stream_key(settings_.verify_secret, "verify", {batch_id_, job.begin, job.end});
  return static_cast<double>(key >> 11) * 0x1.0p-53 < settings_.verify_fraction;
}

bool Dispatcher::on_probation(const Worker& worker) const {
  return settings_.verify_fraction > 0 && !worker.view.local && worker.view.checks_passed < settings_.probation_checks;
}

void Dispatcher::pass_check(const WorkerId& id) {
  const auto it = workers_.find(id);
  if (it == workers_.end()) return;
  it->second.view.checks_passed += 1;
}

void Dispatcher::note_unchecked(const WorkerId& id) {
  if (settings_.verify_fraction > 0) ledger_.note_unchecked(id, batch_id_);
}

size_t Dispatcher::proven_workers() const {
  return static_cast<size_t>(
      std::count_if(workers_.begin(), workers_.end(), [](const auto& w) { return w.second.view.proven; }));
}

void Dispatcher::prove(Worker& worker) {
  worker.view.proven = true;
  worker.view.demoted = false;
}

void Dispatcher::demote(Worker& worker) {
  if (worker.view.demoted) return;
  worker.view.demoted = true;
  demoted_ += 1;
}

void Dispatcher::on_result(const WorkerId& id, const wire::Result& result, Millis now) {
  const auto worker = workers_.find(id);
  const auto job = jobs_.find(result.job_id());
  const auto lease = job == jobs_.end() ? std::vector<Lease>::iterator{}
                                        : std::find_if(job->second.leases.begin(), job->second.leases.end(),
                                                       [&](const Lease& l) { return l.worker == id; });
  const bool holds = job != jobs_.end() && lease != job->second.leases.end();
  const bool taken_back = worker != workers_.end() && job != jobs_.end() && job->second.taken_back.erase(id) > 0;
  if (worker == workers_.end() || job == jobs_.end() || (!holds && !taken_back)) {
    // a job its backup finished first; or a stranger, or a job this worker no longer holds (re-queued, or done)
    const bool late = worker != workers_.end() && worker->second.beaten.erase(result.job_id()) > 0;
    count_drop(late ? DropReason::kLateResult : DropReason::kUnexpectedResult);
    // the answer to its trial, come after its batch ended
    const bool trial =
        worker != workers_.end() && worker->second.trial_since && worker->second.trial_job == result.job_id();
    if (!late && !trial) return;
    // a late answer still shows the worker alive and answering when it parses (a new worker beaten at every
    // batch's tail by proven ones would otherwise never be proven, and one whose trial outlived its batch would
    // be demoted)
    worker->second.trial_since.reset();
    bool parses = !result.has_error() && result.results_size() > 0;
    for (int i = 0; parses && i < result.results_size(); ++i) parses = result_from_wire(result.results(i)).has_value();
    if (parses) prove(worker->second);
    return;
  }
  worker->second.trial_since.reset();  // it answered a job it held, rightly or not
  Worker& w = worker->second;
  Job& j = job->second;
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
  const size_t count = j.end - j.begin;
  std::vector<RolloutResult> parsed;
  bool valid = result.results_size() == static_cast<int>(count);
  for (int i = 0; valid && i < result.results_size(); ++i) {
    Expected<RolloutResult> r = result_from_wire(result.results(i));
    if (r) parsed.push_back(std::move(*r));
    valid = r.has_value();
  }
  if (!valid) {  // a worker that sends nonsense is treated as one that died with the job
    count_drop(DropReason::kBadResult);
    if (!w.view.proven) demote(w);
    j.leases.push_back({id, now});  // released below as by a death
    release(j.id, w, /*died=*/true);
    return;
  }
  prove(w);  // alive and answering; whether it computes right is its probation's to say
  w.view.jobs_done += 1;
  w.view.results_done += static_cast<int64_t>(count);
  if (holds) {  // a result taken back from an expired lease says nothing of how long jobs take
    job_times_.add(took);
    backup_after_ =
        std::max(settings_.backup_min_ms, static_cast<Millis>(settings_.backup_factor * job_times_.median()));
  }
  on_answer(w, j, std::move(parsed));
}

void Dispatcher::on_error(Worker& worker, Job& job, const std::string& error) {
  job.failed.insert(worker.view.id);
  if (!worker.view.proven) {
    // a peer that never returned a result cannot stop the run: the job goes to a proven worker
    count_drop(DropReason::kErrorFromUnproven);
    demote(worker);
    job.tainted = true;
    if (job.leases.empty()) requeue(job, false);
    return;
  }
  job.refusing.insert(worker.view.id);
  refusals_seen_ = true;
  job.tainted = true;
  if (job.refusing.size() >= std::min<size_t>(2, std::max<size_t>(1, proven_workers()))) {
    if (!failure_)
      failure_ = "worker " + worker.view.name + " refused " + describe_task(job.begin) +
                 (job.end - job.begin > 1 ? " (or a later task of its job)" : "") + ": " + error +
                 (job.refusing.size() > 1 ? " (and so did " + std::to_string(job.refusing.size() - 1) +
                                                " other worker" + (job.refusing.size() > 2 ? "s" : "") + ")"
                                          : "");
    return;
  }
  if (job.leases.empty()) requeue(job, false);  // another proven worker says whether the error is real
}

void Dispatcher::on_answer(Worker& worker, Job& job, std::vector<RolloutResult> results) {
  const bool check = (job.verify || on_probation(worker)) && (!worker.view.local || !job.answers.empty());
  if (!check) {
    const bool trusted = settings_.verify_fraction <= 0 || worker.view.local;
    if (!trusted) note_unchecked(worker.view.id);
    accept(job, results, worker.view.id, trusted);
    return;
  }
  if (job.answers.empty()) {
    job.answers.push_back({worker.view.id, std::move(results)});
    if (job.leases.empty()) enqueue_front(job);  // for a second worker
    return;
  }
  if (job.answers.size() == 1) {
    if (same_results(job.answers[0].results, results)) {
      verified_ += 1;
      pass_check(job.answers[0].worker);
      pass_check(worker.view.id);
      accept(job, results, job.answers[0].worker, true);
      return;
    }
    if (worker.view.local) {  // a worker this coordinator started decides at once
      refuse_wrong(job.answers[0].worker);
      accept(job, results, worker.view.id, true);
      return;
    }
    job.answers.push_back({worker.view.id, std::move(results)});
    if (job.leases.empty()) enqueue_front(job);  // a third worker decides
    return;
  }
  // the third answer decides between two that differ
  const bool first = same_results(job.answers[0].results, results);
  const bool second = same_results(job.answers[1].results, results);
  if (!first && !second) {
    if (!failure_)
      failure_ = "three workers returned three different results for " + describe_task(job.begin) +
                 " (or a later task of its job): do they run one build? (compare --fingerprint)";
    return;
  }
  verified_ += 1;
  pass_check(first ? job.answers[0].worker : job.answers[1].worker);
  pass_check(worker.view.id);
  // refused first: its results held back must not become final with this job, which may be the batch's last
  refuse_wrong(first ? job.answers[1].worker : job.answers[0].worker);
  accept(job, results, worker.view.id, true);  // ends the job
}

void Dispatcher::accept(Job& job, const std::vector<RolloutResult>& results, const WorkerId& from, bool final_now) {
  results_.put(job.begin, results, from, final_now);
  for (const Lease& other : job.leases) {  // the other holders' results, when they come, are late
    const auto it = workers_.find(other.worker);
    if (it == workers_.end()) continue;
    it->second.jobs.erase(job.id);
    it->second.beaten.insert(job.id);
  }
  if (job.queued) remove_from_queue(job.id);
  jobs_.erase(job.id);
}

void Dispatcher::refuse_wrong(const WorkerId id, const char* why) {  // a copy: the answers it may name are erased
  const auto it = workers_.find(id);
  if (!ledger_.refuse(id, it != workers_.end() ? it->second.view.name : id, batch_id_)) return;
  // its answers awaiting a check are worth nothing: those jobs wait for answers from others
  for (auto& [job_id, job] : jobs_) {
    const size_t before = job.answers.size();
    std::erase_if(job.answers, [&](const Answer& a) { return a.worker == id; });
    if (job.answers.size() != before && job.leases.empty()) enqueue_front(job);
  }
  if (it != workers_.end()) {
    Outgoing refusal{id, {}};
    refusal.message.mutable_refused()->set_reason(why);
    refusals_.push_back(std::move(refusal));
    remove_worker(id, /*died=*/false);
  }
  // every result of the batch taken from it is computed again, by others
  // (those reported final were checked by another worker, or came from a local one: they stand)
  for (const auto& [first, end] : results_.withdraw(id))
    new_jobs(first, end, static_cast<size_t>(settings_.max_chunk), 0, /*front=*/true);
}

std::vector<WorkerId> Dispatcher::expire(Millis now) {
  std::vector<WorkerId> dead;
  for (const Worker* worker : arrival_)
    if (now - worker->view.last_heard > settings_.liveness_ms) dead.push_back(worker->view.id);
  for (const WorkerId& id : dead) lose_worker(id);
  return dead;
}

Millis Dispatcher::lease_ms() const { return backup_after_ > 0 ? backup_after_ : settings_.liveness_ms; }

void Dispatcher::expire_leases(Millis now) {
  const Millis lease = lease_ms();
  // leases of proven workers never expire (they are backed up): with none held by others, no job need be looked at
  if (unproven_holding()) expire_unproven_leases(now, lease);
  // a job it held ended with its batch, unanswered, and the lease has run out since
  for (auto& [id, worker] : workers_)
    if (!worker.view.proven && worker.jobs.empty() && worker.trial_since && now - *worker.trial_since >= lease)
      demote(worker);
}

bool Dispatcher::unproven_holding() const {
  return std::any_of(arrival_.begin(), arrival_.end(),
                     [](const Worker* w) { return !w->view.proven && !w->jobs.empty(); });
}

void Dispatcher::expire_unproven_leases(Millis now, Millis lease) {
  for (auto& [job_id, job] : jobs_) {
    const size_t before = job.leases.size();
    std::erase_if(job.leases, [&](const Lease& l) {
      if (now - l.since < lease) return false;
      Worker& holder = workers_.at(l.worker);
      if (holder.view.proven) return false;  // a slow machine: backed up, not taken back
      holder.jobs.erase(job_id);
      job.taken_back.insert(l.worker);
      job.failed.insert(l.worker);
      demote(holder);
      return true;
    });
    if (job.leases.size() == before) continue;
    leases_expired_ += static_cast<int64_t>(before - job.leases.size());
    job.tainted = true;
    if (job.leases.empty()) enqueue_front(job);
  }
}

bool Dispatcher::proven_can_take(const Job& job) const {
  return std::any_of(workers_.begin(), workers_.end(),
                     [&](const auto& w) { return w.second.ready && w.second.view.proven && may_take(job, w.second); });
}

bool Dispatcher::may_take(const Job& job, const Worker& worker) const {
  const WorkerId& id = worker.view.id;
  if (job.failed.contains(id)) return false;
  if (std::any_of(job.leases.begin(), job.leases.end(), [&](const Lease& l) { return l.worker == id; })) return false;
  if (std::any_of(job.answers.begin(), job.answers.end(), [&](const Answer& a) { return a.worker == id; }))
    return false;
  if (!job.answers.empty() && !worker.view.proven) return false;  // a check: one that never answered may sit on it
  if (worker.view.proven || !job.tainted) return true;
  // a job a worker not proven failed goes to a worker not proven only when no proven one may take it, and never
  // as a check (the coordinator checks it instead)
  return job.answers.empty() && !proven_can_take(job);
}

Dispatcher::Job* Dispatcher::next_job(const Worker& worker, Millis now) {
  size_t scanned = 0;
  for (auto it = queue_.begin(); it != queue_.end() && scanned < kQueueScan; ++it, ++scanned) {
    Job& job = jobs_.at(*it);
    if (!may_take(job, worker)) continue;
    queue_.erase(it);
    job.queued = false;
    return &job;
  }
  // Nothing queued: a worker not proven is sent a copy of an open job, the one with the fewest holders, as its
  // trial, so that however many silent peers joined first and took the batch's jobs, the real workers among the
  // new ones get one too and prove themselves within a job's time (each peer holds one trial at a time, and is
  // demoted when it lets one run past its lease).
  if (!worker.view.proven) {
    Job* fewest = nullptr;
    for (auto& [job_id, job] : jobs_) {
      if (job.queued || job.leases.empty() || !may_take(job, worker)) continue;
      if (fewest == nullptr || job.leases.size() < fewest->leases.size()) fewest = &job;
    }
    return fewest;
  }
  // Nothing queued: a proven worker takes at once a job held only by workers not proven, since those may never
  // answer; so peers that take jobs and sit on them delay nothing while a proven worker is free.
  if (spare_.unproven_holding) {
    for (auto& [job_id, job] : jobs_) {
      // (trials pile onto a job beyond max_leases: they do not count, the first proven holder does)
      if (job.queued || job.leases.empty()) continue;
      const bool unproven_only = std::none_of(job.leases.begin(), job.leases.end(),
                                              [&](const Lease& l) { return workers_.at(l.worker).view.proven; });
      if (!unproven_only || !may_take(job, worker)) continue;
      return &job;
    }
  }
  if (!spare_.overdue) return nullptr;
  // a backup: a job whose every holder has held it past the lease (proven ones: slow, or silent)
  const Millis lease = lease_ms();
  Job* oldest = nullptr;
  Millis oldest_since = 0;
  for (auto& [job_id, job] : jobs_) {
    if (job.queued || job.leases.empty() || job.leases.size() >= static_cast<size_t>(settings_.max_leases)) continue;
    Millis newest = 0;
    for (const Lease& l : job.leases) newest = std::max(newest, l.since);
    if (now - newest < lease || !may_take(job, worker)) continue;
    if (!worker.view.proven && job.tainted) continue;
    if (oldest == nullptr || newest < oldest_since) {
      oldest = &job;
      oldest_since = newest;
    }
  }
  if (oldest != nullptr) backups_ += 1;
  return oldest;
}

Dispatcher::Spare Dispatcher::spare_jobs(Millis now) const {
  Spare spare;
  spare.unproven_holding = unproven_holding();
  if (settings_.backup_factor <= 0) return spare;
  const Millis lease = lease_ms();
  spare.overdue = std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& entry) {
    const Job& job = entry.second;
    if (job.queued || job.leases.empty() || job.leases.size() >= static_cast<size_t>(settings_.max_leases))
      return false;
    return std::all_of(job.leases.begin(), job.leases.end(), [&](const Lease& l) { return now - l.since >= lease; });
  });
  return spare;
}

bool Dispatcher::eligible_checker(const Job& job, const Worker& worker) const {
  return worker.ready && !worker.view.demoted && may_take(job, worker);  // may_take: proven workers only
}

void Dispatcher::check_unanswerable(Millis now) {
  coordinator_checks_waiting_ = 0;
  if (refusals_seen_) {  // (otherwise no queued job has been refused: none to look at)
    const size_t proven = proven_workers();
    for (const uint64_t id : queue_) {
      const Job& job = jobs_.at(id);
      // proven workers that refused it may now be all there are (the others left): the error rule says again
      if (!job.refusing.empty() && job.refusing.size() >= std::min<size_t>(2, std::max<size_t>(1, proven)) && !failure_)
        failure_ = "workers refused " + describe_task(job.begin) + " (" + std::to_string(job.refusing.size()) +
                   " of the " + std::to_string(proven) + " proven workers connected)";
    }
  }
  const Millis lease = lease_ms();
  if (settings_.verify_fraction <= 0) return;  // answers are held only to be checked
  for (auto& [id, job] : jobs_) {
    if (job.answers.empty()) continue;
    // queued with no connected worker able to check it, or held for a check past the lease (a proven worker that
    // answered once may still sit on it, and proven holders' leases do not expire): the coordinator checks it
    const bool stuck = job.queued ? std::none_of(workers_.begin(), workers_.end(),
                                                 [&](const auto& w) { return eligible_checker(job, w.second); })
                                  : std::all_of(job.leases.begin(), job.leases.end(),
                                                [&](const Lease& l) { return now - l.since >= lease; });
    if (!stuck) continue;
    coordinator_checks_waiting_ += 1;
    if (!std::exchange(job.to_coordinator, true)) to_coordinator_.push_back(id);
  }
}

std::vector<Dispatcher::CoordinatorCheck> Dispatcher::take_coordinator_checks() {
  std::vector<CoordinatorCheck> out;
  for (const uint64_t id : std::exchange(to_coordinator_, {})) {
    const auto it = jobs_.find(id);
    if (!batch_active_ || it == jobs_.end()) continue;
    const Job& job = it->second;
    out.push_back({batch_id_, id, job.answers.size() > 1,
                   std::vector<RolloutTask>(tasks_.begin() + static_cast<std::ptrdiff_t>(job.begin),
                                            tasks_.begin() + static_cast<std::ptrdiff_t>(job.end))});
  }
  return out;
}

bool Dispatcher::awaits_coordinator(uint64_t batch_id, uint64_t job_id) const {
  return batch_active_ && batch_id == batch_id_ && jobs_.contains(job_id);
}

void Dispatcher::settle_by_coordinator(uint64_t batch_id, uint64_t job_id, const std::vector<RolloutResult>& results) {
  if (!batch_active_ || batch_id != batch_id_) return;
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;  // a worker's answer settled it first
  Job& job = it->second;
  if (results.size() != job.end - job.begin) return;
  coordinator_checks_ += 1;
  std::vector<WorkerId> wrong;
  for (const Answer& answer : job.answers) {
    if (same_results(answer.results, results)) {
      verified_ += 1;
      pass_check(answer.worker);
    } else {
      wrong.push_back(answer.worker);
    }
  }
  // refused first: their results held back must not become final with this job, which may be the batch's last
  for (const WorkerId& id : wrong)
    refuse_wrong(id, "this worker returned results that the coordinator, computing them itself, did not");
  accept(job, results, kCoordinatorAnswer, true);  // ends the job
}

void Dispatcher::send(Job& job, Worker& worker, Millis now, const std::function<void(Outgoing&&)>& deliver) {
  const WorkerId& id = worker.view.id;
  job.leases.push_back({id, now});
  worker.jobs.insert(job.id);
  if (!worker.view.proven && !worker.trial_since) {
    worker.trial_since = now;
    worker.trial_job = job.id;
  }
  if (!worker.view.proven) spare_.unproven_holding = true;
  deliver(encoder_.job(id, job.id, job.begin, job.end, worker.thetas_sent));
  worker.last_sent = now;
}

std::vector<Outgoing> Dispatcher::outgoing(Millis now) {
  std::vector<Outgoing> out;
  outgoing(now, [&](Outgoing&& message) { out.push_back(std::move(message)); });
  return out;
}

void Dispatcher::outgoing(Millis now, const std::function<void(Outgoing&&)>& deliver) {
  for (Outgoing& refusal : std::exchange(refusals_, {})) deliver(std::move(refusal));
  if (batch_active_) {
    expire_leases(now);
    check_unanswerable(now);
  }
  if (batch_active_) spare_ = spare_jobs(now);
  // One job per worker per pass, so a batch spreads over every worker before any gets a second. But with queued
  // jobs enough to fill every worker, a worker's free places are filled at once, with consecutive jobs: these
  // mostly share a θ, and θ is most of a job's bytes.
  const bool fill_at_once =
      batch_active_ && queue_.size() >= static_cast<size_t>(settings_.jobs_ahead) * ready_workers();
  for (bool assigned = true; assigned && !failure_ && batch_active_;) {
    assigned = false;
    for (Worker* held : arrival_) {
      Worker& worker = *held;
      // a worker not yet proven holds one job at a time; a demoted one none
      const size_t room = worker.view.proven ? static_cast<size_t>(settings_.jobs_ahead) : 1;
      if (!worker.ready || worker.view.demoted || worker.jobs.size() >= room) continue;
      if (!worker.view.proven && worker.trial_since) continue;  // a job of an earlier batch still unanswered
      for (size_t places = fill_at_once ? room - worker.jobs.size() : 1; places > 0; --places) {
        Job* job = next_job(worker, now);
        if (job == nullptr) break;
        send(*job, worker, now, deliver);
        assigned = true;
      }
    }
  }
  for (Worker* held : arrival_) {
    Worker& worker = *held;
    if (now - worker.last_sent < settings_.heartbeat_ms) continue;
    Outgoing beat{worker.view.id, {}};
    beat.message.mutable_heartbeat();
    deliver(std::move(beat));
    worker.last_sent = now;
  }
}

void Dispatcher::start_batch(std::span<const RolloutTask> tasks) {
  abandon_batch();
  batch_active_ = true;
  batch_id_ += 1;
  // a worker gone, with no answer held any more, can no longer be found wrong
  ledger_.forget_workers([&](const WorkerId& id) { return !workers_.contains(id); });
  tasks_.assign(tasks.begin(), tasks.end());
  results_.start(tasks.size());
  encoder_.start_batch(tasks_, batch_id_);
  for (auto& [id, worker] : workers_) worker.thetas_sent.clear();

  new_jobs(0, tasks.size(), tasks_per_job(tasks.size()), 0, /*front=*/false);
}

size_t Dispatcher::tasks_per_job(size_t tasks) const {
  size_t threads = 0, workers = 0;
  for (const auto& [id, worker] : workers_) {
    if (!worker.ready || worker.view.demoted) continue;
    threads += static_cast<size_t>(worker.view.threads);
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
  for (auto& [id, worker] : workers_) {  // their late results will be dropped
    worker.jobs.clear();
    worker.beaten.clear();
  }
  job_times_.clear();
  backup_after_ = 0;
  refusals_seen_ = false;
  to_coordinator_.clear();
  jobs_.clear();
  queue_.clear();
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

size_t Dispatcher::ready_workers() const {
  return static_cast<size_t>(std::count_if(workers_.begin(), workers_.end(),
                                           [](const auto& w) { return w.second.ready && !w.second.view.demoted; }));
}

int64_t Dispatcher::in_flight() const {
  int64_t n = 0;
  for (const auto& [id, worker] : workers_) n += static_cast<int64_t>(worker.jobs.size());
  return n;
}

std::vector<WorkerView> Dispatcher::workers() const {
  std::vector<WorkerView> out;
  for (const Worker* worker : arrival_) {
    WorkerView view = worker->view;
    view.jobs_held = worker->jobs.size();
    out.push_back(std::move(view));
  }
  return out;
}

DispatchView Dispatcher::view(Millis now) const {
  DispatchView v;
  v.workers = workers();
  v.at = now;
  v.ready_workers = ready_workers();
  v.queue_depth = queue_depth();
  v.in_flight_jobs = in_flight();
  v.dropped_frames = dropped_;
  v.workers_joined = joined_;
  v.workers_lost = lost_;
  v.backup_jobs = backups_;
  v.leases_expired = leases_expired_;
  v.workers_demoted = demoted_;
  v.verified_jobs = verified_;
  v.wrong_workers = static_cast<int64_t>(ledger_.names().size());
  v.coordinator_checks = coordinator_checks_;
  v.rollbacks = ledger_.rollbacks();
  return v;
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
