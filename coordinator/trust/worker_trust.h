#pragma once
// How far the coordinator trusts its workers: the rule book of the referee (referee.h), as decisions on the records
// it is given — may this worker take this job, what does this answer settle, must the run go back and to where.
// Pure: no queue, no sockets, no clock of its own (its verdicts follow from the standings and jobs it is given, and
// what it has recorded). It holds verification (which answers are checked, what they say), the refusal ledger, the
// coordinator's own checks waiting and the rollback record; the standing of each worker (standing.h) and the checks
// of each job (job_trust.h) are the referee's records, changed only here.
//
// Trust. A worker is proven — alive and answering — once it has returned a valid result (or, started by this
// coordinator, from its Hello: it showed local_token); whether its answers are right is verification's to say.
// Until then its death, an error it returns or a lease it lets expire only takes the job back (the job is then
// tainted and goes to proven workers only, while any is connected), and the latter two demote it (no more jobs).
// The run stops on an error only when two proven witnesses (or the only one connected; the connections of one CURVE
// key are one) refuse the job: a real error repeats, runs being deterministic.
//
// Verification. With verify_fraction > 0, every answer of a worker on probation (not local, and fewer than
// probation_checks of its answers checked and found right) and a fraction of the other answers of workers that are
// not local are also computed by another witness — a proven worker of another CURVE key (or connection, without
// CURVE), past probation where the answers held were all given on probation or differ — and the results must match
// bit for bit; verification.h states the rules of independent witnesses by which answers confirm, refute or wait
// for the coordinator (a local worker's answer, or the coordinator's, decides at once). An answer held for a check
// is compared with the job's next answer, and a holder beaten to a job answers late and is compared with the results
// taken. Which jobs are checked is drawn from verify_secret, the batch and the job's
// tasks: a worker that does not know the secret cannot tell which of its answers will be checked, so one lying on k
// answers after probation goes unnoticed with probability (1 - verify_fraction)^k whichever it chooses. The worker
// found wrong is refused from then on. Unchecked answers of workers that are not local are final only once their
// batch is whole; once they are, only going back to a state computed before them undoes them: take_rollback names
// the first batch to compute again when a worker refused had unchecked answers made final.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "coordinator/trust/effects.h"
#include "coordinator/trust/job_trust.h"
#include "coordinator/trust/refusal_ledger.h"
#include "coordinator/trust/standing.h"
#include "coordinator/trust/verification.h"
#include "simulation/rollout.h"

namespace poet {

// Who answered a task the coordinator computed itself: no routing id can equal it (a peer's own id may not start
// with a zero byte, and libzmq's generated ones are five bytes).
inline const WorkerId kCoordinatorAnswer("\0the coordinator", 16);

struct TrustSettings {
  double verify_fraction = 0;  // of the jobs answered by workers that are not local, also run on a second
  uint64_t verify_secret = 0;  // which jobs are checked: drawn from it, the batch and the job; never sent
  int probation_checks = 5;    // with verification: every answer of a worker not local is checked until this many were
};

// Whether a worker may take a job (beyond holding it already, which is the queue's to say).
enum class Eligibility {
  kNo,
  kYes,
  kIfNoProvenCan,  // a tainted job, to a worker not proven: only when no proven worker connected may take it
};

// What an answer settles. The dispatcher credits `passed` with a check each and refuses `wrong` (their results held
// back must not become final with this job), then acts on the kind.
struct Settlement {
  enum class Kind {
    kTake,         // take `results` from `credited`: final at once (final_now), or held back until the batch is whole
    kHold,         // the answer is held with the job (or, of a witness held already, dropped): it waits for another's
    kStands,       // a late answer: the results taken stand
    kReopen,       // a late answer differs from the results taken: the tasks go out again holding `reopened`
    kCoordinator,  // three answers held and none confirmed: the coordinator decides (ask_coordinator)
  };
  Kind kind = Kind::kHold;
  WorkerId credited;
  bool final_now = true;
  bool checked = false;  // kTake: another answer was compared with it
  std::vector<RolloutResult> results;
  std::vector<WorkerId> passed;           // answers found right
  std::vector<WorkerId> wrong;            // workers found wrong: refused before the results are taken
  std::string why_wrong;                  // what they did, after their name ("returned results that ...")
  std::optional<WorkerId> checked_since;  // kStands: its answer, taken unchecked, was compared since
  std::vector<Answer> reopened;
};

class WorkerTrust {
 public:
  explicit WorkerTrust(TrustSettings settings)
      : verification_(settings.verify_fraction, settings.verify_secret, settings.probation_checks) {}

  bool verifies() const { return verification_.enabled(); }

  // Joining and standing.
  bool refused(const WorkerId& id) const { return ledger_.refused(id); }
  // A worker that said Hello, vouched for by `witness` (its CURVE key; empty: its routing id `id`); a local worker is
  // proven from the start.
  Standing newcomer(const WorkerId& id, const Witness& witness, bool local) const;
  Trust level(const Standing& worker) const;
  bool on_probation(const Standing& worker) const { return verification_.on_probation(worker); }
  // Jobs it may hold at once: none when demoted, or not proven with its trial (a job sent, in this batch or an
  // earlier one) unanswered; one while not proven or on probation (its answers wait for checks: its probation ends
  // within about probation_checks of its jobs, not twice that); else jobs_ahead.
  size_t jobs_at_once(const Standing& worker, bool trial_unanswered, size_t jobs_ahead) const;
  // A worker not proven whose trial, sent at `trial_since`, has run a lease without an answer and that holds nothing
  // now (its batch ended): demoted; true if it was just now.
  bool trial_ran_out(Standing& worker, std::optional<Millis> trial_since, bool holding, Millis now, Millis lease);
  // A valid answer: alive and answering, proven and no longer demoted (`counted`: an answer to a job it held, which
  // counts towards what it answered on probation).
  void answered(Standing& worker, bool counted) const;
  void demote(Standing& worker);  // given no more jobs (counted once)
  void passed_check(Standing& worker) const { worker.checks_passed += 1; }
  // One of its answers taken as a job's results, with another compared or without.
  void took_answer(Standing& worker, bool checked) const;
  void checked_since(Standing& worker) const;  // one taken unchecked was compared since, and found right

  // Jobs.
  JobTrust new_job(uint64_t batch, size_t begin, size_t end) const;  // chosen for a check or not, by the secret
  bool chosen(uint64_t batch, size_t begin, size_t end) const { return verification_.chosen(batch, begin, end); }
  Eligibility may_take(const JobTrust& job, const WorkerId& id, const Standing& worker) const;
  // A holder died with the job: whether that counts towards the poison rule (a proven worker's death); a worker not
  // proven proves nothing by dying, and taints the job.
  bool death_counts(JobTrust& job, const Standing& holder) const;
  void lease_ran_out(JobTrust& job, const WorkerId& id, Standing& holder);  // holder not proven: demoted
  // `proven_witnesses`: the witnesses of the proven workers connected (connections of one key are one).
  ErrorVerdict error(JobTrust& job, const WorkerId& id, Standing& worker, size_t proven_witnesses);
  // The error rule: proven witnesses agree the job fails (two, or the only one connected).
  bool refused_by_enough(const JobTrust& job, size_t proven_witnesses) const;

  // What an answer settles: a job's holder's answer in `batch`; the late answer of a holder beaten to it, against
  // the results taken (whose, and whether final: a final one was checked or local, and decides); the coordinator's
  // own results for a job handed to it.
  Settlement answer(JobTrust& job, const WorkerId& id, Standing& worker, std::vector<RolloutResult> results,
                    uint64_t batch);
  Settlement late_answer(Answer taken, bool taken_final, Answer late, bool late_local);
  // An answer that a worker gives now: its witness and whether on probation, for judging and holding.
  Answer answer_of(const WorkerId& id, const Standing& worker, std::vector<RolloutResult> results) const {
    return {id, std::move(results), worker.witness, on_probation(worker)};
  }
  // Whose witness an answer taken for this batch's results had (its worker may be gone since): recorded as taken.
  void credit(const WorkerId& id, const Witness& witness) { credited_[id] = witness; }
  Answer taken_answer(const WorkerId& id, std::vector<RolloutResult> results) const;
  Settlement coordinator_answer(const JobTrust& job, std::vector<RolloutResult> results);

  // The coordinator's own checks: a job holding answers that waits in the queue with no connected worker able to
  // check it, or whose every holder took it at least a lease ago (`newest_lease`: a proven worker that answered
  // once may still sit on it, and proven holders' leases do not expire), waits for the coordinator's own answer:
  // true while it does; it is handed over once (take_coordinator_jobs hands the ids over).
  bool coordinator_must_check(uint64_t job_id, JobTrust& job, bool queued, bool checker_connected, Millis newest_lease,
                              Millis now, Millis lease);
  void ask_coordinator(uint64_t job_id, JobTrust& job);  // at once: three answers held and none confirmed
  std::vector<uint64_t> take_coordinator_jobs() { return std::exchange(to_coordinator_, {}); }

  // Refusing: a worker found wrong, or sharing a wrong one's identity, while batch `current` runs (false when it was
  // refused already). Its answers held with jobs are worth nothing, nor are those of its witness (its CURVE key's
  // other connections): forget_answers_of drops them from one (true if it held any).
  bool refuse(const WorkerId& id, Refusal refusal, uint64_t current) {
    return ledger_.refuse(id, std::move(refusal), current);
  }
  bool forget_answers_of(JobTrust& job, const WorkerId& id, const Witness& witness) const;

  // Going back: the first batch to compute again, once a worker was refused after unchecked answers of its became
  // final; for each worker that may still be found wrong, the first batch of such an answer (what the caller must be
  // able to go back to); the caller went back to before `batch`; a batch starts (workers gone can no longer be
  // found wrong); it ends (the coordinator's checks waiting are void).
  std::optional<uint64_t> take_rollback() { return ledger_.take_rollback(); }
  std::optional<uint64_t> rollback_asked() const { return ledger_.rollback_asked(); }  // the same, not taken yet
  std::vector<uint64_t> unchecked_since() const { return ledger_.unchecked_since(); }
  void forget_batches_from(uint64_t batch) { ledger_.forget_batches_from(batch); }
  void start_batch(const std::function<bool(const WorkerId&)>& gone) {
    ledger_.forget_workers(gone);
    credited_.clear();
  }
  void end_batch() { to_coordinator_.clear(); }

  // Answers found right by a second worker or the coordinator
  int64_t verified() const { return verification_.verified(); }
  int64_t coordinator_checks() const { return verification_.coordinator_checks(); }  // jobs settled by its answer
  int64_t rollbacks() const { return ledger_.rollbacks(); }
  int64_t demoted() const { return demoted_; }
  const std::vector<Refusal>& refusals() const { return ledger_.refusals(); }  // in order
  const std::set<WorkerId>& refused_ids() const { return ledger_.refused_ids(); }

 private:
  Verification verification_;
  RefusalLedger ledger_;
  std::vector<uint64_t> to_coordinator_;  // jobs handed to the coordinator, not yet taken
  std::map<WorkerId, Witness> credited_;  // the witness of each worker whose answer this batch took
  int64_t demoted_ = 0;
};

}  // namespace poet
