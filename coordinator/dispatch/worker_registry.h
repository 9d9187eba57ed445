#pragma once
// Who is connected: the workers in the order they said Hello, when each was last heard from, what each holds, and
// its trial (not proven, sent a job it has not answered yet). Each points at its standing (how far it is trusted:
// the referee's record, coordinator/trust/referee.h, read here to count and to choose). Time is a parameter; no
// queue, no sockets.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"

namespace poet {

struct RegisteredWorker {
  WorkerFacts facts;
  const Standing* standing = nullptr;  // the referee's record of it, there until it leaves
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

  // The tasks of a job it held and another holder finished first, once (nullopt: not such a job).
  std::optional<std::pair<size_t, size_t>> take_beaten(uint64_t job);
};

// A worker as the status socket shows it: its facts, its standing and its jobs held (its trust level is the
// referee's to fill).
WorkerView view_of(const RegisteredWorker& worker);

class WorkerRegistry {
 public:
  // A worker welcomed (its facts from its Hello, its standing the referee's); it must not be registered already.
  RegisteredWorker& add(WorkerFacts facts, const Standing& standing, Millis now);
  // Removed, and handed back to the caller (its jobs to release); nullopt for an unknown id. `refused`: kept as it
  // was, shown among the latest kMaxRefusedShown refused (refused_views).
  std::optional<RegisteredWorker> remove(const WorkerId& id, bool refused = false);
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
  // Those sent nothing for `every` ms, in order: each is sent a heartbeat now.
  std::vector<WorkerId> heartbeats_due(Millis now, Millis every);
  // A batch starts: no θ sent to anyone yet; the threads of each worker that may be sent jobs (ready, not demoted).
  std::vector<int> batch_started();
  void batch_ended();  // nothing held any more: results that still come are late
  // A job sent to it; a worker not proven is on trial from its first one until it answers.
  void sent_job(RegisteredWorker& worker, uint64_t job_id, Millis now);

  size_t proven() const;
  size_t ready() const;                   // those that may be sent jobs
  bool unproven_holding() const;          // some worker not proven holds a job
  int64_t jobs_held() const;              // by all of them
  std::vector<WorkerView> views() const;  // in order, each with its standing and jobs held
  int64_t joined() const { return joined_; }
  const std::deque<WorkerView>& refused_views() const { return refused_; }  // in order

 private:
  std::unordered_map<WorkerId, RegisteredWorker> by_id_;
  std::vector<RegisteredWorker*> arrival_;  // by_id_'s entries in the order they said Hello
  int64_t joined_ = 0;
  std::deque<WorkerView> refused_;
};

}  // namespace poet
