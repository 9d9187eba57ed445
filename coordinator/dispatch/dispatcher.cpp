#include "dispatch/dispatcher.h"

#include <algorithm>
#include <cstdio>

#include "rollout_task_proto.h"

namespace poet {
namespace {

std::string hex64(uint64_t value) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

}  // namespace

wire::CoordinatorMessage Dispatcher::on_hello(const WorkerId& id, const wire::Hello& hello, Millis now) {
  wire::CoordinatorMessage reply;
  if (hello.protocol_version() != wire::PROTOCOL_VERSION) {
    count_drop("wrong_version");
    reply.mutable_refused()->set_reason("protocol version " + std::to_string(hello.protocol_version()) +
                                        ", the coordinator speaks " + std::to_string(wire::PROTOCOL_VERSION));
    return reply;
  }
  if (settings_.fingerprint_digest != 0 && hello.fingerprint_digest() != settings_.fingerprint_digest) {
    count_drop("wrong_fingerprint");
    reply.mutable_refused()->set_reason("build fingerprint " + hex64(hello.fingerprint_digest()) +
                                        " differs from the coordinator's " + hex64(settings_.fingerprint_digest) +
                                        ": its returns would differ (compare --fingerprint of both binaries)");
    return reply;
  }
  if (workers_.contains(id)) remove_worker(id, /*died=*/false);  // said Hello again: a fresh start
  if (workers_.size() >= settings_.max_workers) {
    count_drop("worker_limit");
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
  worker.last_sent = now;
  workers_.emplace(id, std::move(worker));
  arrival_.push_back(id);
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
  const std::set<uint64_t> held = it->second.jobs;
  workers_.erase(it);
  std::erase(arrival_, id);
  // back to the front, in their order, so the batch finishes in the order it was cut
  for (auto job = held.rbegin(); job != held.rend(); ++job) release(*job, id, died);
}

void Dispatcher::release(uint64_t job_id, const WorkerId& id, bool died) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  std::erase_if(it->second.leases, [&](const Lease& lease) { return lease.worker == id; });
  // a backed-up job still held by its other worker stays with it: that worker's result will do
  if (it->second.leases.empty()) requeue(job_id, died);
}

void Dispatcher::requeue(uint64_t job_id, bool died) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  Job job = it->second;
  jobs_.erase(it);
  job.leases.clear();
  if (!died) {
    jobs_.emplace(job.id, job);
    queue_.push_front(job.id);
    return;
  }
  // A job whose worker died may hold a task that kills workers: it is retried one task per job, so the task
  // that does is found and named.
  const int deaths = job.deaths + 1;
  std::vector<uint64_t> parts;
  for (size_t t = job.begin; t < job.end; ++t) {
    if (have_result_[t]) continue;
    if (deaths >= settings_.max_attempts) {
      if (!failure_)
        failure_ = describe_task(t) + " was running on " + std::to_string(deaths) +
                   " workers when they died; the run stops rather than lose more workers to it";
      continue;
    }
    Job part{next_job_id_++, t, t + 1, deaths, {}};
    jobs_.emplace(part.id, part);
    parts.push_back(part.id);
  }
  for (auto p = parts.rbegin(); p != parts.rend(); ++p) queue_.push_front(*p);
}

void Dispatcher::on_result(const WorkerId& id, const wire::Result& result, Millis now) {
  const auto worker = workers_.find(id);
  const auto job = jobs_.find(result.job_id());
  const auto lease = job == jobs_.end() ? std::vector<Lease>::iterator{}
                                        : std::find_if(job->second.leases.begin(), job->second.leases.end(),
                                                       [&](const Lease& l) { return l.worker == id; });
  if (worker == workers_.end() || job == jobs_.end() || lease == job->second.leases.end()) {
    // a job its backup finished first; or a stranger, or a job this worker no longer holds (re-queued, or done)
    count_drop(worker != workers_.end() && worker->second.beaten.erase(result.job_id()) ? "late_result"
                                                                                        : "unexpected_result");
    return;
  }
  const Millis took = now - lease->since;
  worker->second.view.last_heard = now;
  worker->second.jobs.erase(job->first);
  if (result.has_error()) {
    if (result.missing_theta()) {  // the worker dropped θs it was sent: send them again
      worker->second.thetas_sent.clear();
      release(job->first, id, false);
      return;
    }
    if (!failure_)
      failure_ = "worker " + worker->second.view.name + " refused " + describe_task(job->second.begin) +
                 (job->second.end - job->second.begin > 1 ? " (or a later task of its job)" : "") + ": " +
                 result.error();
    release(job->first, id, false);
    return;
  }
  const Job& j = job->second;
  const size_t count = j.end - j.begin;
  std::vector<RolloutResult> parsed;
  bool valid = result.results_size() == static_cast<int>(count);
  for (int i = 0; valid && i < result.results_size(); ++i) {
    Expected<RolloutResult> r = result_from_wire(result.results(i));
    if (r) parsed.push_back(std::move(*r));
    valid = r.has_value();
  }
  if (!valid) {  // a worker that sends nonsense is treated as one that died with the job
    count_drop("bad_result");
    release(job->first, id, true);
    return;
  }
  for (size_t k = 0; k < count; ++k) {
    results_[j.begin + k] = parsed[k];
    if (!have_result_[j.begin + k]) remaining_ -= 1;
    have_result_[j.begin + k] = true;
  }
  ready_ranges_.emplace_back(j.begin, j.end);
  worker->second.view.jobs_done += 1;
  worker->second.view.results_done += static_cast<int64_t>(count);
  for (const Lease& other : j.leases) {  // the other holder's result, when it comes, is late
    if (other.worker == id) continue;
    Worker& loser = workers_.at(other.worker);
    loser.jobs.erase(j.id);
    loser.beaten.insert(j.id);
  }
  jobs_.erase(job);

  job_times_.push_back(took);
  std::vector<Millis> times = job_times_;
  const auto middle = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
  std::nth_element(times.begin(), middle, times.end());
  backup_after_ = std::max(settings_.backup_min_ms, static_cast<Millis>(settings_.backup_factor * *middle));
}

std::vector<WorkerId> Dispatcher::expire(Millis now) {
  std::vector<WorkerId> dead;
  for (const WorkerId& id : arrival_)
    if (now - workers_.at(id).view.last_heard > settings_.liveness_ms) dead.push_back(id);
  for (const WorkerId& id : dead) remove_worker(id, /*died=*/true);
  lost_ += static_cast<int64_t>(dead.size());
  return dead;
}

wire::Job Dispatcher::job_message(const Job& job, Worker& worker) const {
  wire::Job out;
  out.set_job_id(job.id);
  out.set_batch_id(batch_id_);
  for (size_t t = job.begin; t < job.end; ++t) {
    const uint64_t hash = task_theta_hash_[t];
    if (worker.thetas_sent.insert(hash).second) {
      wire::Theta* theta = out.add_thetas();
      theta->set_hash(hash);
      const std::vector<double>& values = *thetas_.at(hash);
      theta->mutable_values()->Add(values.begin(), values.end());
    }
    *out.add_tasks() = to_wire(tasks_[t], hash);
  }
  return out;
}

void Dispatcher::send(Job& job, const WorkerId& id, Millis now, std::vector<Outgoing>& out) {
  Worker& worker = workers_.at(id);
  job.leases.push_back({id, now});
  worker.jobs.insert(job.id);
  Outgoing message{id, {}};
  *message.message.mutable_job() = job_message(job, worker);
  out.push_back(std::move(message));
  worker.last_sent = now;
}

Dispatcher::Job* Dispatcher::straggler(const WorkerId& id, Millis now) {
  if (settings_.backup_factor <= 0) return nullptr;
  const Millis after = backup_after_ > 0 ? backup_after_ : settings_.liveness_ms;
  Job* oldest = nullptr;
  for (auto& [job_id, job] : jobs_) {
    if (job.leases.size() != 1 || job.leases[0].worker == id || now - job.leases[0].since < after) continue;
    if (oldest == nullptr || job.leases[0].since < oldest->leases[0].since) oldest = &job;
  }
  return oldest;
}

std::vector<Outgoing> Dispatcher::outgoing(Millis now) {
  std::vector<Outgoing> out;
  // one job per worker per pass, so a batch spreads over every worker before any gets a second
  for (bool assigned = true; assigned && !failure_;) {
    assigned = false;
    for (const WorkerId& id : arrival_) {
      Worker& worker = workers_.at(id);
      if (!worker.ready || worker.jobs.size() >= static_cast<size_t>(settings_.jobs_ahead)) continue;
      Job* job = nullptr;
      if (!queue_.empty()) {
        job = &jobs_.at(queue_.front());
        queue_.pop_front();
      } else if ((job = straggler(id, now)) != nullptr) {
        backups_ += 1;
      } else {
        continue;
      }
      send(*job, id, now, out);
      assigned = true;
    }
  }
  for (const WorkerId& id : arrival_) {
    Worker& worker = workers_.at(id);
    if (now - worker.last_sent < settings_.heartbeat_ms) continue;
    Outgoing beat{id, {}};
    beat.message.mutable_heartbeat();
    out.push_back(std::move(beat));
    worker.last_sent = now;
  }
  return out;
}

void Dispatcher::start_batch(std::span<const RolloutTask> tasks) {
  abandon_batch();
  batch_active_ = true;
  batch_id_ += 1;
  tasks_.assign(tasks.begin(), tasks.end());
  results_.assign(tasks.size(), RolloutResult{});
  have_result_.assign(tasks.size(), false);
  remaining_ = tasks.size();
  task_theta_hash_.clear();
  std::unordered_map<const std::vector<double>*, uint64_t> hash_of;  // tasks of a batch share a few θs
  for (const RolloutTask& task : tasks_) {
    const std::vector<double>* theta = task.theta.get();
    auto [it, fresh] = hash_of.emplace(theta, 0);
    if (fresh) it->second = theta_hash(*theta);
    task_theta_hash_.push_back(it->second);
    thetas_[it->second] = theta;
  }
  for (auto& [id, worker] : workers_) worker.thetas_sent.clear();

  // about four jobs per thread of the workers present, so that a slow or lost worker delays little
  int threads = 0;
  for (const auto& [id, worker] : workers_)
    if (worker.ready) threads += worker.view.threads;
  const size_t per_job = std::clamp<size_t>((tasks.size() + 4 * std::max(threads, 1) - 1) / (4 * std::max(threads, 1)),
                                            1, static_cast<size_t>(settings_.max_chunk));
  for (size_t begin = 0; begin < tasks.size(); begin += per_job) {
    const Job job{next_job_id_++, begin, std::min(begin + per_job, tasks.size()), 0, {}};
    jobs_.emplace(job.id, job);
    queue_.push_back(job.id);
  }
}

void Dispatcher::abandon_batch() {
  for (auto& [id, worker] : workers_) {  // their late results will be dropped
    worker.jobs.clear();
    worker.beaten.clear();
  }
  job_times_.clear();
  backup_after_ = 0;
  jobs_.clear();
  queue_.clear();
  tasks_.clear();
  thetas_.clear();
  task_theta_hash_.clear();
  results_.clear();
  have_result_.clear();
  ready_ranges_.clear();
  remaining_ = 0;
  batch_active_ = false;
}

std::vector<RolloutResult> Dispatcher::take_results() {
  std::vector<RolloutResult> out = std::move(results_);
  abandon_batch();
  return out;
}

std::vector<std::pair<size_t, size_t>> Dispatcher::take_ready_ranges() { return std::exchange(ready_ranges_, {}); }

size_t Dispatcher::ready_workers() const {
  return static_cast<size_t>(
      std::count_if(workers_.begin(), workers_.end(), [](const auto& w) { return w.second.ready; }));
}

int64_t Dispatcher::in_flight() const {
  int64_t n = 0;
  for (const auto& [id, worker] : workers_) n += static_cast<int64_t>(worker.jobs.size());
  return n;
}

std::vector<WorkerView> Dispatcher::workers() const {
  std::vector<WorkerView> out;
  for (const WorkerId& id : arrival_) {
    WorkerView view = workers_.at(id).view;
    view.jobs_held = workers_.at(id).jobs.size();
    out.push_back(std::move(view));
  }
  return out;
}

std::string Dispatcher::describe_task(size_t index) const {
  const RolloutTask& task = tasks_.at(index);
  std::string text = "task " + std::to_string(index) + " of the batch (course " + task.env.encoding.name + " seed " +
                     std::to_string(task.env.seed) + ", θ " + hex64(task_theta_hash_.at(index));
  if (task.perturbation)
    text += ", perturbation " + hex64(task.perturbation->key) + " sign " + std::to_string(task.perturbation->sign);
  return text + ")";
}

}  // namespace poet
