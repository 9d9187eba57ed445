#pragma once
// The referee of the workers' answers: one object that takes each event of verification — a worker joins or leaves,
// a job opens or closes, an answer, a late answer, an error, the coordinator's own answer, a lease or a trial run
// out, a job stuck with answers no one can check — and returns what to do (effects.h): take these results, hold
// the job for another answer, reopen tasks with both answers held, run a job on the coordinator, refuse these
// workers and keys, stop the run. It owns trust's records: each worker's standing, each open job's checks, the
// refusals and the rollback record; the dispatcher reads them (const) to schedule, and applies the effects in one
// place — as WorkerSession turns the worker's events into actions. WorkerTrust (worker_trust.h) is its rule book,
// verification.h the rules of independent witnesses. Pure: no queue, no sockets, no clock of its own.
//
// A worker found wrong is refused by its routing id and, with CURVE, by its key: every worker holding the key is
// refused with it (effects; one gone since is refused too, its results not final withdrawn), and so is any Hello
// with it from then on. Going back is a record, not an
// effect of one event: rollback_asked names the first batch whose final results may hold a lie, and the caller
// goes back (went_back) once its batch is over.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "coordinator/trust/effects.h"
#include "coordinator/trust/worker_trust.h"

namespace poet {

class Referee {
 public:
  explicit Referee(TrustSettings settings) : trust_(settings) {}

  bool verifies() const { return trust_.verifies(); }

  // Workers. Why a Hello is refused (its routing id or CURVE key refused for wrong results), if it is; a worker
  // joining (`key`: its connection's CURVE key, empty without CURVE; `local`: started by this coordinator), whose
  // standing stays where it is until it leaves and names it in the events below; a worker gone (Goodbye, silence,
  // a failed send, refused).
  std::optional<std::string> hello_refused(const WorkerId& id, const std::string& key) const;
  const Standing& joined(const WorkerId& id, const std::string& name, const std::string& key, bool local);
  void left(const WorkerId& id);
  Trust level(const Standing& worker) const { return trust_.level(worker); }
  size_t jobs_at_once(const Standing& worker, bool trial_unanswered, size_t jobs_ahead) const {
    return trust_.jobs_at_once(worker, trial_unanswered, jobs_ahead);
  }

  // Jobs. A job of tasks [begin, end) of `batch` opened (holding `held`: a disputed answer reopened), whose record
  // stays where it is until the batch ends (ids come in order, one more each time, as JobQueue gives them); whether
  // a worker may take it.
  const JobTrust& opened(uint64_t job, uint64_t batch, size_t begin, size_t end, std::vector<Answer> held = {});
  void closed(uint64_t job) {  // its answers forgotten; the record goes with the batch
    if (JobTrust& closed = record(job); !closed.answers.empty()) closed.answers.clear();
  }
  const JobTrust& job(uint64_t job) const { return jobs_.at(job - first_job_); }
  Eligibility may_take(const JobTrust& job, const WorkerId& id, const Standing& worker) const {
    return trust_.may_take(job, id, worker);
  }

  // Events of a batch (`batch`: the one running).
  // A holder's valid answer: alive and answering; taken, held, or settling a check. `worker`: as joined() gave it.
  Effects answer(uint64_t job, const Standing& worker, std::vector<RolloutResult> results, uint64_t batch);
  // An answer come late (its job done, or its trial's batch over) that parses: the worker is alive and answering.
  void answered_late(const WorkerId& id);
  // The late answer of a holder beaten to tasks [begin, end) by `taken_from`, whose results were taken (`taken_final`:
  // reported final, so checked or local), compared with them.
  Effects late_answer(const WorkerId& id, std::vector<RolloutResult> late, const WorkerId& taken_from,
                      std::span<const RolloutResult> taken, bool taken_final, size_t begin, size_t end, uint64_t batch);
  // An error Result for a job: the error rule counts witnesses (two, or the only one connected), so workers that
  // share a key are one.
  Effects error(uint64_t job, const Standing& worker);
  // The coordinator's own results for a job handed to it.
  Effects coordinator_answer(uint64_t job, std::vector<RolloutResult> results, uint64_t batch);
  // A holder not proven let its lease run out, or sent nonsense: demoted. A holder died with the job: whether that
  // counts towards the poison rule (it was proven).
  void lease_ran_out(uint64_t job, const Standing& worker);
  void sent_nonsense(const Standing& worker);
  bool died_with(uint64_t job, const Standing& worker);
  // A worker not proven whose trial, sent at `trial_since`, ran a lease unanswered while it holds nothing: demoted.
  bool trial_ran_out(const Standing& worker, std::optional<Millis> trial_since, bool holding, Millis now, Millis lease);
  // A job holding answers, waiting in the queue (`queued`) with no connected worker able to check it
  // (`checker_connected`), or whose every holder took it a lease ago (`newest_lease`): the coordinator checks it.
  Effects stuck(uint64_t job, bool queued, bool checker_connected, Millis newest_lease, Millis now, Millis lease);
  // The error rule, asked again of a queued job: proven workers that refused it are now enough.
  bool refused_by_enough(uint64_t job) const { return trust_.refused_by_enough(this->job(job), proven_witnesses()); }

  // Batches and going back. A batch starts (workers gone can no longer be found wrong) or ends (its jobs close);
  // the first batch to compute again, not yet gone back to; what must stay reachable meanwhile; the caller went back
  // to the state after `last_batch` (the rollback asked for is taken, counted once).
  void batch_started();
  void batch_ended();
  std::optional<uint64_t> rollback_asked() const { return trust_.rollback_asked(); }
  std::vector<uint64_t> unchecked_since() const { return trust_.unchecked_since(); }
  void went_back(uint64_t last_batch);

  // What it has counted: answers found right by a second witness or the coordinator, jobs settled by the
  // coordinator's own answer, times it sent the run back, workers not proven demoted.
  struct Counts {
    int64_t verified = 0;
    int64_t coordinator_checks = 0;
    int64_t rollbacks = 0;
    int64_t demoted = 0;
  };
  Counts counts() const {
    return {trust_.verified(), trust_.coordinator_checks(), trust_.rollbacks(), trust_.demoted()};
  }
  const std::vector<Refusal>& refusals() const { return trust_.refusals(); }  // in order

 private:
  // A worker's standing and what else the referee keeps of it: joined() hands out the standing, and the events
  // name the worker by it.
  struct WorkerRecord : Standing {
    WorkerId id;
    std::string name;
    std::string key;        // its CURVE key (empty without CURVE)
    bool connected = true;  // gone workers are kept until the batch ends: their held answers may still be judged
  };

  Standing* connected(const WorkerId& id);
  size_t proven_witnesses() const;  // of the proven workers connected, two at most: all the error rule asks
  // The record behind a standing joined() handed out (the referee's own object, so its own to change).
  static WorkerRecord& record_of(const Standing& worker) {
    return static_cast<WorkerRecord&>(const_cast<Standing&>(worker));
  }
  JobTrust& record(uint64_t job) { return jobs_.at(job - first_job_); }
  // What a settlement says: those found right credited with a check, those found wrong refused, then the rest.
  // `answering`: the worker whose answer settled it, if a worker's.
  void settle(uint64_t job, Settlement&& settlement, uint64_t batch, Effects& out, Standing* answering = nullptr);
  // A worker found wrong: refused, its answers and those of its witness forgotten (their jobs wait for others'),
  // and with CURVE its key and every connected worker holding it.
  void refuse(const WorkerId& id, const std::string& why, uint64_t batch, Effects& out);

  WorkerTrust trust_;
  std::unordered_map<WorkerId, WorkerRecord> workers_;
  // The batch's jobs by id, from first_job_ on: a batch's job ids are consecutive, and a deque keeps each record
  // where it is as others are added (one allocation a few hundred jobs, where a map made one a job).
  std::deque<JobTrust> jobs_;
  uint64_t first_job_ = 0;
  std::set<std::string> refused_keys_;
};

}  // namespace poet
