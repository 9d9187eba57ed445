#pragma once
// Who is connected: the workers in the order they said Hello, when each was last heard from, what each holds, and
// its trial (not proven, sent a job it has not answered yet). Each keeps its standing in its view (how far it is
// trusted: WorkerTrust's to change, read here to count and to choose). Time is a parameter; no queue, no sockets.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"

namespace poet {

struct RegisteredWorker {
  WorkerView view;
  std::set<uint64_t> jobs;  // held
  // held, then finished by another holder first: its result is late, and compared with the one taken (its tasks)
  std::map<uint64_t, std::pair<size_t, size_t>> beaten;
  std::set<uint64_t> thetas_sent;  // this batch
  Millis last_sent = 0;
  // not proven: when it was sent a job it has not answered since (in this batch or an earlier one); it is sent
  // nothing more until it answers, and demoted once that is a lease ago
  std::optional<Millis> trial_since;
  uint64_t trial_job = 0;  // the job then sent
  bool ready = false;      // has sent something since its Hello
};

class WorkerRegistry {
 public:
  // A worker welcomed (its view filled from its Hello, its standing from trust); it must not be registered already.
  RegisteredWorker& add(WorkerView view, Millis now);
  // Removed, and handed back to the caller (its jobs to release); nullopt for an unknown id.
  std::optional<RegisteredWorker> remove(const WorkerId& id);
  RegisteredWorker* find(const WorkerId& id);
  const RegisteredWorker* find(const WorkerId& id) const;
  bool contains(const WorkerId& id) const { return by_id_.contains(id); }
  bool is_proven(const WorkerId& id) const;  // false for an unknown id
  // A predicate for JobQueue's holder tests: true for an id not proven (or unknown).
  auto not_proven() const {
    return [this](const WorkerId& id) { return !is_proven(id); };
  }
  size_t size() const { return by_id_.size(); }
  // In the order they said Hello: jobs go out in this order.
  const std::vector<RegisteredWorker*>& in_order() const { return arrival_; }

  bool heard_from(const WorkerId& id, Millis now);  // any message: alive and listening; false for a stranger
  std::vector<WorkerId> silent(Millis now, Millis liveness) const;  // heard from longer ago than liveness
  // A job sent to it; a worker not proven is on trial from its first one until it answers.
  void sent_job(RegisteredWorker& worker, uint64_t job_id, Millis now);

  size_t proven() const;
  size_t ready() const;                   // those that may be sent jobs
  bool unproven_holding() const;          // some worker not proven holds a job
  int64_t jobs_held() const;              // by all of them
  std::vector<WorkerView> views() const;  // in order, each with its jobs held
  int64_t joined() const { return joined_; }

 private:
  std::unordered_map<WorkerId, RegisteredWorker> by_id_;
  std::vector<RegisteredWorker*> arrival_;  // by_id_'s entries in the order they said Hello
  int64_t joined_ = 0;
};

}  // namespace poet
