#include "coordinator/dispatch/worker_registry.h"

#include <algorithm>
#include <utility>

namespace poet {

RegisteredWorker& WorkerRegistry::add(WorkerView view, Millis now) {
  RegisteredWorker worker;
  worker.view = std::move(view);
  worker.view.last_heard = now;
  worker.last_sent = now;
  const WorkerId id = worker.view.id;
  RegisteredWorker& added = by_id_.emplace(id, std::move(worker)).first->second;
  arrival_.push_back(&added);
  joined_ += 1;
  return added;
}

std::optional<RegisteredWorker> WorkerRegistry::remove(const WorkerId& id) {
  const auto it = by_id_.find(id);
  if (it == by_id_.end()) return std::nullopt;
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
  return worker != nullptr && worker->view.proven;
}

bool WorkerRegistry::heard_from(const WorkerId& id, Millis now) {
  RegisteredWorker* worker = find(id);
  if (worker == nullptr) return false;
  worker->view.last_heard = now;
  worker->ready = true;
  return true;
}

std::vector<WorkerId> WorkerRegistry::silent(Millis now, Millis liveness) const {
  std::vector<WorkerId> out;
  for (const RegisteredWorker* worker : arrival_)
    if (now - worker->view.last_heard > liveness) out.push_back(worker->view.id);
  return out;
}

void WorkerRegistry::sent_job(RegisteredWorker& worker, uint64_t job_id, Millis now) {
  worker.jobs.insert(job_id);
  if (!worker.view.proven && !worker.trial_since) {
    worker.trial_since = now;
    worker.trial_job = job_id;
  }
  worker.last_sent = now;
}

size_t WorkerRegistry::proven() const {
  return static_cast<size_t>(
      std::count_if(arrival_.begin(), arrival_.end(), [](const RegisteredWorker* w) { return w->view.proven; }));
}

size_t WorkerRegistry::ready() const {
  return static_cast<size_t>(std::count_if(arrival_.begin(), arrival_.end(),
                                           [](const RegisteredWorker* w) { return w->ready && !w->view.demoted; }));
}

bool WorkerRegistry::unproven_holding() const {
  return std::any_of(arrival_.begin(), arrival_.end(),
                     [](const RegisteredWorker* w) { return !w->view.proven && !w->jobs.empty(); });
}

int64_t WorkerRegistry::jobs_held() const {
  int64_t n = 0;
  for (const RegisteredWorker* worker : arrival_) n += static_cast<int64_t>(worker->jobs.size());
  return n;
}

std::vector<WorkerView> WorkerRegistry::views() const {
  std::vector<WorkerView> out;
  for (const RegisteredWorker* worker : arrival_) {
    WorkerView view = worker->view;
    view.jobs_held = worker->jobs.size();
    out.push_back(std::move(view));
  }
  return out;
}

}  // namespace poet
