#include "coordinator/trust/refusal_ledger.h"

#include <utility>

namespace poet {

bool RefusalLedger::refuse(const WorkerId& id, Refusal refusal, uint64_t current) {
  if (!refused_.insert(id).second) return false;
  // unchecked answers of an earlier batch are final: the run must go back to before them
  if (const auto since = unchecked_since_.find(id); since != unchecked_since_.end()) {
    if (since->second < current && (!rollback_from_ || since->second < *rollback_from_)) rollback_from_ = since->second;
    unchecked_since_.erase(since);
  }
  refusals_.push_back(std::move(refusal));
  return true;
}

void RefusalLedger::forget_workers(const std::function<bool(const WorkerId&)>& gone) {
  std::erase_if(unchecked_since_, [&](const auto& entry) { return gone(entry.first); });
}

void RefusalLedger::forget_batches_from(uint64_t batch) {
  std::erase_if(unchecked_since_, [&](const auto& entry) { return entry.second >= batch; });
}

std::optional<uint64_t> RefusalLedger::take_rollback() {
  if (rollback_from_) rollbacks_ += 1;
  return std::exchange(rollback_from_, std::nullopt);
}

std::vector<uint64_t> RefusalLedger::unchecked_since() const {
  std::vector<uint64_t> out;
  for (const auto& [id, batch] : unchecked_since_) out.push_back(batch);
  if (rollback_from_) out.push_back(*rollback_from_);  // asked for, not yet taken
  return out;
}

}  // namespace poet
