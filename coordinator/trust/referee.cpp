#include "coordinator/trust/referee.h"

#include <stdexcept>
#include <utility>

namespace poet {
namespace {

const char* const kHoldsRefusedKey = "holds the CURVE key of a worker refused for wrong results";

}  // namespace

std::optional<std::string> Referee::hello_refused(const WorkerId& id, const std::string& key) const {
  if (trust_.refused(id)) return "this worker was refused for wrong results";
  if (!key.empty() && refused_keys_.contains(key)) return std::string("this worker ") + kHoldsRefusedKey;
  return std::nullopt;
}

const Standing& Referee::joined(const WorkerId& id, const std::string& name, const std::string& key, bool local) {
  // in place: a routing id freed and taken again is a new worker, and the record's address stays the same
  WorkerRecord& record = workers_[id];
  record = {trust_.newcomer(id, key, local), id, name, key, true};
  return record;
}

void Referee::left(const WorkerId& id) {
  if (const auto it = workers_.find(id); it != workers_.end()) it->second.connected = false;
}

Standing* Referee::connected(const WorkerId& id) {
  const auto it = workers_.find(id);
  return it != workers_.end() && it->second.connected ? &it->second : nullptr;
}

size_t Referee::proven_witnesses() const {
  const Witness* first = nullptr;
  for (const auto& [id, worker] : workers_) {
    if (!worker.connected || !worker.proven) continue;
    const Witness& witness = worker.witness.empty() ? id : worker.witness;
    if (first == nullptr)
      first = &witness;
    else if (witness != *first)
      return 2;
  }
  return first == nullptr ? 0 : 1;
}

const JobTrust& Referee::opened(uint64_t job, uint64_t batch, size_t begin, size_t end, std::vector<Answer> held) {
  if (jobs_.empty()) first_job_ = job;
  if (job < first_job_ + jobs_.size()) throw std::logic_error("a job opened twice, or out of order");
  while (first_job_ + jobs_.size() < job) jobs_.emplace_back();
  JobTrust& opened = jobs_.emplace_back();
  opened.chosen = trust_.chosen(batch, begin, end);
  opened.answers = std::move(held);
  return opened;
}

Effects Referee::answer(uint64_t job, const Standing& answering, std::vector<RolloutResult> results, uint64_t batch) {
  Effects out;
  WorkerRecord& worker = record_of(answering);
  const WorkerId& id = worker.id;
  trust_.answered(worker, /*counted=*/true);  // alive and answering; whether it computes right is probation's to say
  JobTrust& trust = record(job);
  Settlement settlement = trust_.answer(trust, id, worker, std::move(results), batch);
  switch (settlement.kind) {
    case Settlement::Kind::kHold:  // for a second witness, or a third to decide
      out.requeue.push_back(job);
      break;
    case Settlement::Kind::kCoordinator:  // three answers and none confirmed: not sent out again
      trust_.ask_coordinator(job, trust);
      out.to_coordinator = trust_.take_coordinator_jobs();
      break;
    default:
      settle(job, std::move(settlement), batch, out, &worker);
  }
  return out;
}

void Referee::answered_late(const WorkerId& id) {
  if (Standing* worker = connected(id)) trust_.answered(*worker, /*counted=*/false);
}

Effects Referee::late_answer(const WorkerId& id, std::vector<RolloutResult> late, const WorkerId& taken_from,
                             std::span<const RolloutResult> taken, bool taken_final, size_t begin, size_t end,
                             uint64_t batch) {
  Effects out;
  const Standing* worker = connected(id);
  if (worker == nullptr) return out;
  Settlement settlement = trust_.late_answer(trust_.taken_answer(taken_from, {taken.begin(), taken.end()}), taken_final,
                                             trust_.answer_of(id, *worker, std::move(late)), worker->local);
  if (settlement.kind == Settlement::Kind::kReopen) {  // two answers that differ: a third decides
    out.reopen = Effects::Reopen{begin, end, std::move(settlement.reopened)};
    return out;
  }
  if (settlement.checked_since)
    if (Standing* taken_worker = connected(*settlement.checked_since)) trust_.checked_since(*taken_worker);
  // the taken answer found wrong: its results not final are withdrawn and computed again
  settle(0, std::move(settlement), batch, out);
  return out;
}

Effects Referee::error(uint64_t job, const Standing& worker) {
  Effects out;
  WorkerRecord& refusing = record_of(worker);
  out.error = trust_.error(record(job), refusing.id, refusing, proven_witnesses());
  if (*out.error != ErrorVerdict::kStop) out.requeue.push_back(job);
  return out;
}

Effects Referee::coordinator_answer(uint64_t job, std::vector<RolloutResult> results, uint64_t batch) {
  Effects out;
  settle(job, trust_.coordinator_answer(record(job), std::move(results)), batch, out);
  return out;
}

void Referee::lease_ran_out(uint64_t job, const Standing& worker) {
  WorkerRecord& holder = record_of(worker);
  trust_.lease_ran_out(record(job), holder.id, holder);
}

void Referee::sent_nonsense(const Standing& worker) {
  if (!worker.proven) trust_.demote(record_of(worker));
}

bool Referee::died_with(uint64_t job, const Standing& worker) { return trust_.death_counts(record(job), worker); }

bool Referee::trial_ran_out(const Standing& worker, std::optional<Millis> trial_since, bool holding, Millis now,
                            Millis lease) {
  return trust_.trial_ran_out(record_of(worker), trial_since, holding, now, lease);
}

Effects Referee::stuck(uint64_t job, bool queued, bool checker_connected, Millis newest_lease, Millis now,
                       Millis lease) {
  Effects out;
  trust_.coordinator_must_check(job, record(job), queued, checker_connected, newest_lease, now, lease);
  out.to_coordinator = trust_.take_coordinator_jobs();
  return out;
}

void Referee::settle(uint64_t job, Settlement&& settlement, uint64_t batch, Effects& out, Standing* answering) {
  for (const WorkerId& id : settlement.passed)
    if (Standing* passed = connected(id)) trust_.passed_check(*passed);
  for (const WorkerId& id : settlement.wrong) refuse(id, settlement.why_wrong, batch, out);
  if (settlement.kind != Settlement::Kind::kTake) return;
  // taken unchecked, it is the answer just given: its worker is at hand (the common case, without a lookup)
  Standing* credited = answering != nullptr && !settlement.checked ? answering : connected(settlement.credited);
  if (credited != nullptr) {
    trust_.took_answer(*credited, settlement.checked);
    trust_.credit(settlement.credited, credited->witness);
  }
  out.take = Effects::Take{job, settlement.credited, settlement.final_now, std::move(settlement.results)};
}

void Referee::refuse(const WorkerId& id, const std::string& why, uint64_t batch, Effects& out) {
  const auto record = workers_.find(id);
  const bool known = record != workers_.end();
  if (!trust_.refuse(id, {known ? record->second.name : id, why}, batch)) return;
  // its answers awaiting a check, and those of its key's other connections (gone ones too), are worth nothing: those
  // jobs wait for answers from others
  const Witness witness = known && !record->second.witness.empty() ? record->second.witness : id;
  for (size_t i = 0; i < jobs_.size(); ++i)
    if (trust_.forget_answers_of(jobs_[i], id, witness)) out.requeue.push_back(first_job_ + i);
  out.refuse.push_back({id, why});  // gone or not: its results not final are withdrawn
  // with CURVE, its key: refused before it is told, so that it cannot come back on a new socket, and every other
  // connection holding it at once, rather than when one of its own lies happens to be drawn for a check
  if (!known || record->second.key.empty() || !refused_keys_.insert(record->second.key).second) return;
  const std::string key = record->second.key;
  out.refuse_keys.push_back(key);
  for (const auto& [peer, other] : workers_)
    if (other.key == key) refuse(peer, kHoldsRefusedKey, batch, out);  // gone ones too, as their answers held
}

void Referee::batch_started() {
  // a worker gone, with no answer held any more, can no longer be found wrong
  std::erase_if(workers_, [](const auto& entry) { return !entry.second.connected; });
  trust_.start_batch([&](const WorkerId& id) { return !workers_.contains(id); });
}

void Referee::batch_ended() {
  jobs_.clear();
  trust_.end_batch();
}

void Referee::went_back(uint64_t last_batch) {
  trust_.take_rollback();  // done: counted once
  trust_.forget_batches_from(last_batch + 1);
}

}  // namespace poet
