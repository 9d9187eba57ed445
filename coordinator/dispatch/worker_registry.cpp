#include "coordinator/dispatch/worker_registry.h"

#include <algorithm>
#include <utility>

namespace poet {

WorkerView view_of(const RegisteredWorker& worker) {
  WorkerView view;
  static_cast<Standing&>(view) = *worker.standing;
  static_cast<WorkerFacts&>(view) = worker.facts;
  view.jobs_held = worker.jobs.size();
  return view;
}

RegisteredWorker& WorkerRegistry::add(WorkerFacts facts, const Standing& standing, Millis now) {
  RegisteredWorker worker;
  worker.facts = std::move(facts);
  worker.standing = &standing;
  worker.facts.last_heard = now;
  worker.last_sent = now;
  const WorkerId id = worker.facts.id;
  RegisteredWorker& added = by_id_.emplace(id, std::move(worker)).first->second;
  arrival_.push_back(&added);
  joined_ += 1;
  return added;
}

std::optional<RegisteredWorker> WorkerRegistry::remove(const WorkerId& id, bool refused) {
  const auto it = by_id_.find(id);
  if (it == by_id_.end()) return std::nullopt;
  if (refused) {
    WorkerView shown = view_of(it->second);
    shown.trust = Trust::kRefused;
    shown.jobs_held = 0;
    refused_.push_back(std::move(shown));
    if (refused_.size() > kMaxRefusedShown) refused_.pop_front();
  }
  std::erase(arrival_, &it->second);
  RegisteredWorker worker = std::move(it->second);
  by_id_.erase(it);
  return worker;
}

RegisteredWorker* WorkerRegistry::find(const WorkerId& id) {
  const auto it = by_id_.find(id);
  return it == by_id_.end() ? nullptr : &it->second;
}

const RegisteredWorker* WorkerRegistry::find(const WorkerId& id) const {
  const auto it = by_id_.find(id);
  return it == by_id_.end() ? nullptr : &it->second;
}

bool WorkerRegistry::is_proven(const WorkerId& id) const {
  const RegisteredWorker* worker = find(id);
  return worker != nullptr && worker->standing->proven;
}

bool WorkerRegistry::heard_from(const WorkerId& id, Millis now) {
  RegisteredWorker* worker = find(id);
  if (worker == nullptr) return false;
  worker->facts.last_heard = now;
  worker->ready = true;
  return true;
}

std::vector<WorkerId> WorkerRegistry::silent(Millis now, Millis liveness) const {
  std::vector<WorkerId> out;
  for (const RegisteredWorker* worker : arrival_)
    if (now - worker->facts.last_heard > liveness) out.push_back(worker->facts.id);
  return out;
}

std::vector<WorkerId> WorkerRegistry::heartbeats_due(Millis now, Millis every) {
  std::vector<WorkerId> due;
  for (RegisteredWorker* worker : arrival_) {
    if (now - worker->last_sent < every) continue;
    due.push_back(worker->facts.id);
    worker->last_sent = now;
  }
  return due;
}

std::optional<std::pair<size_t, size_t>> RegisteredWorker::take_beaten(uint64_t job) {
  const auto it = beaten.find(job);
  if (it == beaten.end()) return std::nullopt;
  const std::pair<size_t, size_t> tasks = it->second;
  beaten.erase(it);
  return tasks;
}

std::vector<int> WorkerRegistry::batch_started() {
  std::vector<int> threads;
  for (RegisteredWorker* worker : arrival_) {
    worker->thetas_sent.clear();
    if (worker->ready && !worker->standing->demoted) threads.push_back(worker->facts.threads);
  }
  return threads;
}

void WorkerRegistry::batch_ended() {
  for (RegisteredWorker* worker : arrival_) {
    worker->jobs.clear();
    worker->beaten.clear();
  }
}

void WorkerRegistry::sent_job(RegisteredWorker& worker, uint64_t job_id, Millis now) {
  worker.jobs.insert(job_id);
  if (!worker.standing->proven && !worker.trial_since) {
    worker.trial_since = now;
    worker.trial_job = job_id;
  }
  worker.last_sent = now;
}

size_t WorkerRegistry::proven() const {
  return static_cast<size_t>(
      std::count_if(arrival_.begin(), arrival_.end(), [](const RegisteredWorker* w) { return w->standing->proven; }));
}

size_t WorkerRegistry::ready() const {
  return static_cast<size_t>(std::count_if(
      arrival_.begin(), arrival_.end(), [](const RegisteredWorker* w) { return w->ready && !w->standing->demoted; }));
}

bool WorkerRegistry::unproven_holding() const {
  return std::any_of(arrival_.begin(), arrival_.end(),
                     [](const RegisteredWorker* w) { return !w->standing->proven && !w->jobs.empty(); });
}

int64_t WorkerRegistry::jobs_held() const {
  int64_t n = 0;
  for (const RegisteredWorker* worker : arrival_) n += static_cast<int64_t>(worker->jobs.size());
  return n;
}

std::vector<WorkerView> WorkerRegistry::views() const {
  std::vector<WorkerView> out;
  for (const RegisteredWorker* worker : arrival_) out.push_back(view_of(*worker));
  return out;
}

}  // namespace poet
