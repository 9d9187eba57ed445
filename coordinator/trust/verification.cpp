#include "coordinator/trust/verification.h"

#include <algorithm>
#include <bit>

#include "simulation/rng.h"

namespace poet {

bool same_results(const std::vector<RolloutResult>& a, const std::vector<RolloutResult>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::bit_cast<uint64_t>(a[i].total_reward) != std::bit_cast<uint64_t>(b[i].total_reward) ||
        a[i].steps != b[i].steps || a[i].finished != b[i].finished || a[i].fell != b[i].fell)
      return false;
  }
  return true;
}

bool disputed(const std::vector<Answer>& held) {
  return std::any_of(held.begin(), held.end(),
                     [&](const Answer& answer) { return !same_results(answer.results, held[0].results); });
}

bool Verification::chosen(uint64_t batch, size_t begin, size_t end) const {
  if (!enabled()) return false;
  const uint64_t key = stream_key(secret_, "verify", {batch, begin, end});
  return static_cast<double>(key >> 11) * 0x1.0p-53 < fraction_;
}

bool Verification::on_probation(const Standing& worker) const {
  return enabled() && !worker.local && worker.checks_passed < probation_checks_;
}

bool Verification::needs_check(bool job_chosen, const Standing& worker, bool answers_held) const {
  return answers_held || ((job_chosen || on_probation(worker)) && !worker.local);
}

bool Verification::needs_witness_past_probation(const std::vector<Answer>& held) {
  const bool all_on_probation =
      std::all_of(held.begin(), held.end(), [](const Answer& answer) { return answer.probation; });
  return !held.empty() && (all_on_probation || disputed(held));
}

Verdict Verification::judge(const std::vector<Answer>& held, const Answer& incoming, bool incoming_local) {
  Verdict verdict;
  if (held.empty()) return verdict;  // held for another witness
  const auto alike = [&](const Answer& answer) { return same_results(answer.results, incoming.results); };
  const auto take = [&](const WorkerId& credited) {
    verdict.kind = Verdict::Kind::kTake;
    verdict.credited = credited;
    for (const Answer& answer : held) (alike(answer) ? verdict.passed : verdict.wrong).push_back(answer.worker);
  };
  if (incoming_local) {  // a worker this coordinator started decides at once
    const auto first_alike = std::find_if(held.begin(), held.end(), alike);
    take(first_alike != held.end() ? first_alike->worker : incoming.worker);
    if (first_alike != held.end()) {
      verified_ += 1;
      verdict.passed.push_back(incoming.worker);
    }
    return verdict;
  }
  if (std::any_of(held.begin(), held.end(),
                  [&](const Answer& answer) { return answer.vouched_by() == incoming.vouched_by(); })) {
    verdict.keep = false;  // rule 1: not a second witness
    return verdict;
  }
  const bool dispute = std::any_of(held.begin(), held.end(), [&](const Answer& answer) { return !alike(answer); });
  // rule 2: alike, and not both on probation; rule 3: in a dispute, only an answer past probation decides
  const auto confirms = [&](const Answer& answer) {
    return alike(answer) && !(answer.probation && incoming.probation);
  };
  const auto confirmed = std::find_if(held.begin(), held.end(), confirms);
  if (confirmed != held.end() && !(dispute && incoming.probation)) {
    verified_ += 1;
    // an undisputed answer held is credited; a decider is, where it settles a dispute
    take(dispute ? incoming.worker : confirmed->worker);
    verdict.passed.push_back(incoming.worker);
    return verdict;
  }
  if (held.size() + 1 >= 3) verdict.kind = Verdict::Kind::kCoordinator;  // rule 4
  return verdict;
}

CoordinatorVerdict Verification::settle(const std::vector<Answer>& held, const std::vector<RolloutResult>& results) {
  coordinator_checks_ += 1;
  CoordinatorVerdict verdict;
  for (const Answer& answer : held) {
    if (same_results(answer.results, results)) {
      verified_ += 1;
      verdict.passed.push_back(answer.worker);
    } else {
      verdict.wrong.push_back(answer.worker);
    }
  }
  return verdict;
}

}  // namespace poet
