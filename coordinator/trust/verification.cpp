#include "coordinator/trust/verification.h"

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

Verdict Verification::judge(const std::vector<Answer>& held, const Answer& incoming, bool incoming_local) {
  Verdict verdict;
  if (held.empty()) return verdict;  // held for a second worker
  if (held.size() == 1) {
    if (same_results(held[0].results, incoming.results)) {
      verified_ += 1;
      verdict.kind = Verdict::Kind::kTake;
      verdict.credited = held[0].worker;
      verdict.passed = {held[0].worker, incoming.worker};
      return verdict;
    }
    if (incoming_local) {  // a worker this coordinator started decides at once
      verdict.kind = Verdict::Kind::kTake;
      verdict.credited = incoming.worker;
      verdict.wrong = held[0].worker;
    }
    return verdict;  // otherwise a third worker decides
  }
  // the third answer decides between two that differ
  const bool first = same_results(held[0].results, incoming.results);
  const bool second = same_results(held[1].results, incoming.results);
  if (!first && !second) {
    verdict.kind = Verdict::Kind::kThreeWays;
    return verdict;
  }
  verified_ += 1;
  verdict.kind = Verdict::Kind::kTake;
  verdict.credited = incoming.worker;
  verdict.passed = {first ? held[0].worker : held[1].worker, incoming.worker};
  verdict.wrong = first ? held[1].worker : held[0].worker;
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
