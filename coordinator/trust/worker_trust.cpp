#include "coordinator/trust/worker_trust.h"

#include <algorithm>
#include <utility>

namespace poet {
namespace {

const char* const kWrongByWorkers = "returned results that two other workers did not";

}  // namespace

Standing WorkerTrust::newcomer(const WorkerId& id, const Witness& witness, bool local) const {
  Standing standing;
  // a local worker decides for the coordinator, whatever key it shares with remote ones
  standing.witness = witness.empty() || local ? id : witness;
  standing.local = local;
  standing.proven = local;
  return standing;
}

Trust WorkerTrust::level(const Standing& worker) const {
  if (worker.demoted) return Trust::kDemoted;
  if (!worker.proven) return Trust::kTrial;
  return on_probation(worker) ? Trust::kProbation : Trust::kProven;
}

size_t WorkerTrust::jobs_at_once(const Standing& worker, bool trial_unanswered, size_t jobs_ahead) const {
  if (worker.demoted || (!worker.proven && trial_unanswered)) return 0;
  return !worker.proven || on_probation(worker) ? 1 : jobs_ahead;
}

bool WorkerTrust::trial_ran_out(Standing& worker, std::optional<Millis> trial_since, bool holding, Millis now,
                                Millis lease) {
  if (worker.proven || worker.demoted || holding || !trial_since || now - *trial_since < lease) return false;
  demote(worker);
  return true;
}

void WorkerTrust::answered(Standing& worker, bool counted) const {
  worker.proven = true;
  worker.demoted = false;
  if (counted && on_probation(worker)) worker.probation_answers += 1;
}

void WorkerTrust::demote(Standing& worker) {
  if (worker.demoted) return;
  worker.demoted = true;
  demoted_ += 1;
}

void WorkerTrust::took_answer(Standing& worker, bool checked) const {
  worker.answers_taken += 1;
  if (!checked) worker.answers_taken_unchecked += 1;
}

void WorkerTrust::checked_since(Standing& worker) const {
  if (worker.answers_taken_unchecked > 0) worker.answers_taken_unchecked -= 1;
}

JobTrust WorkerTrust::new_job(uint64_t batch, size_t begin, size_t end) const {
  JobTrust job;
  job.chosen = chosen(batch, begin, end);
  return job;
}

Eligibility WorkerTrust::may_take(const JobTrust& job, const WorkerId& id, const Standing& worker) const {
  if (job.failed.contains(id) || job.answered_by(worker.witness.empty() ? id : worker.witness)) return Eligibility::kNo;
  if (!job.answers.empty()) {
    if (!worker.proven) return Eligibility::kNo;  // a check: one that never answered may sit on it
    // answers all given on probation, or differing: only a witness past probation may confirm or decide
    if (on_probation(worker) && Verification::needs_witness_past_probation(job.answers)) return Eligibility::kNo;
  }
  if (worker.proven || !job.tainted) return Eligibility::kYes;
  // a job a worker not proven failed goes to a worker not proven only when no proven one may take it, and never as
  // a check (the coordinator checks it instead)
  return job.answers.empty() ? Eligibility::kIfNoProvenCan : Eligibility::kNo;
}

bool WorkerTrust::death_counts(JobTrust& job, const Standing& holder) const {
  if (holder.proven) return true;
  job.tainted = true;  // a peer that never returned a result proves nothing by dying: a proven worker will say
  return false;
}

void WorkerTrust::lease_ran_out(JobTrust& job, const WorkerId& id, Standing& holder) {
  job.failed.insert(id);
  job.tainted = true;
  demote(holder);
}

ErrorVerdict WorkerTrust::error(JobTrust& job, const WorkerId& id, Standing& worker, size_t proven_witnesses) {
  job.failed.insert(id);
  job.tainted = true;
  if (!worker.proven) {  // a peer that never returned a result cannot stop the run: the job goes to a proven worker
    demote(worker);
    return ErrorVerdict::kFromUnproven;
  }
  job.refusing.insert(worker.witness.empty() ? id : worker.witness);
  return refused_by_enough(job, proven_witnesses) ? ErrorVerdict::kStop : ErrorVerdict::kRetry;
}

bool WorkerTrust::refused_by_enough(const JobTrust& job, size_t proven_witnesses) const {
  return !job.refusing.empty() && job.refusing.size() >= std::min<size_t>(2, std::max<size_t>(1, proven_witnesses));
}

Settlement WorkerTrust::answer(JobTrust& job, const WorkerId& id, Standing& worker, std::vector<RolloutResult> results,
                               uint64_t batch) {
  Settlement out;
  if (!verification_.needs_check(job.chosen, worker, !job.answers.empty())) {
    out.kind = Settlement::Kind::kTake;
    out.credited = id;
    out.final_now = verification_.final_unchecked(worker);
    if (!out.final_now) ledger_.note_unchecked(id, batch);
    out.results = std::move(results);
    return out;
  }
  Answer incoming = answer_of(id, worker, std::move(results));
  Verdict verdict = verification_.judge(job.answers, incoming, worker.local);
  switch (verdict.kind) {
    case Verdict::Kind::kHold:
      if (verdict.keep) job.answers.push_back(std::move(incoming));
      out.kind = Settlement::Kind::kHold;
      return out;
    case Verdict::Kind::kCoordinator:
      job.answers.push_back(std::move(incoming));
      out.kind = Settlement::Kind::kCoordinator;
      return out;
    case Verdict::Kind::kTake:
      out.kind = Settlement::Kind::kTake;
      out.credited = verdict.credited;
      out.checked = true;
      out.results = std::move(incoming.results);
      out.passed = std::move(verdict.passed);
      out.wrong = std::move(verdict.wrong);
      out.why_wrong = kWrongByWorkers;
      return out;
  }
  return out;
}

Answer WorkerTrust::taken_answer(const WorkerId& id, std::vector<RolloutResult> results) const {
  const auto witness = credited_.find(id);
  // taken unchecked, so given past probation; a local worker's or the coordinator's are final, and decide
  return {id, std::move(results), witness != credited_.end() ? witness->second : id, false};
}

Settlement WorkerTrust::late_answer(Answer taken, bool taken_final, Answer late, bool late_local) {
  // results that are final were checked, or came from a local worker or the coordinator: they decide, as a local
  // worker's answer does; otherwise the late answer is judged against the one taken, as a second answer is
  const Verdict verdict = taken_final ? verification_.judge({late}, taken, /*incoming_local=*/true)
                                      : verification_.judge({taken}, late, late_local);
  Settlement out;
  out.kind = Settlement::Kind::kStands;
  if (verdict.kind == Verdict::Kind::kHold && !verdict.keep) return out;  // the taken answer's own witness: no evidence
  if (verdict.kind != Verdict::Kind::kTake) {  // two answers that differ: another witness decides
    out.kind = Settlement::Kind::kReopen;
    out.reopened = {std::move(taken), std::move(late)};
    return out;
  }
  // alike answers of one witness confirm nothing (rule 1), even against final results; one that differs is wrong
  if (late.vouched_by() != taken.vouched_by()) out.passed = verdict.passed;
  out.wrong = verdict.wrong;
  out.why_wrong = kWrongByWorkers;
  if (out.wrong.empty() && !taken_final) out.checked_since = taken.worker;  // taken unchecked, checked now
  return out;
}

Settlement WorkerTrust::coordinator_answer(const JobTrust& job, std::vector<RolloutResult> results) {
  CoordinatorVerdict verdict = verification_.settle(job.answers, results);
  Settlement out;
  out.kind = Settlement::Kind::kTake;
  out.credited = kCoordinatorAnswer;
  out.checked = true;
  out.results = std::move(results);
  out.passed = std::move(verdict.passed);
  out.wrong = std::move(verdict.wrong);
  out.why_wrong = "returned results that the coordinator, computing them itself, did not";
  return out;
}

bool WorkerTrust::coordinator_must_check(uint64_t job_id, JobTrust& job, bool queued, bool checker_connected,
                                         Millis newest_lease, Millis now, Millis lease) {
  if (job.answers.empty()) return false;  // nothing held to check
  const bool stuck = queued ? !checker_connected : now - newest_lease >= lease;
  if (!stuck) return false;
  ask_coordinator(job_id, job);
  return true;
}

void WorkerTrust::ask_coordinator(uint64_t job_id, JobTrust& job) {
  if (!std::exchange(job.to_coordinator, true)) to_coordinator_.push_back(job_id);
}

bool WorkerTrust::forget_answers_of(JobTrust& job, const WorkerId& id, const Witness& witness) const {
  const size_t before = job.answers.size();
  std::erase_if(job.answers, [&](const Answer& a) { return a.worker == id || a.vouched_by() == witness; });
  return job.answers.size() != before;
}

}  // namespace poet
