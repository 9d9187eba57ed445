#pragma once
// What verification remembers across batches: the workers refused for wrong results (by routing id, and their
// names and why in order), and for each worker that may still be found wrong the first batch in which an unchecked
// answer of its became final — so that refusing it says how far back the run must go (a rollback, asked for once).

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coordinator/trust/standing.h"

namespace poet {

// A worker refused, for people: its name and why ("returned results that ...", read after its name).
struct Refusal {
  std::string name;
  std::string why;
};

class RefusalLedger {
 public:
  bool refused(const WorkerId& id) const { return refused_.contains(id); }
  // Refuses a worker found wrong while batch `current` runs; false if it was refused already. Unchecked answers of
  // an earlier batch made final mean the run must go back to before that batch (take_rollback).
  bool refuse(const WorkerId& id, Refusal refusal, uint64_t current);
  // An unchecked answer of this worker became final in `batch` (the first one counts).
  void note_unchecked(const WorkerId& id, uint64_t batch) { unchecked_since_.emplace(id, batch); }
  // Workers that can no longer be found wrong (gone, with nothing held) are forgotten.
  void forget_workers(const std::function<bool(const WorkerId&)>& gone);
  void forget_batches_from(uint64_t batch);  // the caller went back to before `batch`
  std::optional<uint64_t> take_rollback();   // the first batch to compute again, once
  std::optional<uint64_t> rollback_asked() const { return rollback_from_; }  // the same, not taken yet
  // For each worker that may still be found wrong, the first batch of an unchecked final answer; and a rollback
  // asked for and not yet taken.
  std::vector<uint64_t> unchecked_since() const;

  const std::set<WorkerId>& refused_ids() const { return refused_; }
  const std::vector<Refusal>& refusals() const { return refusals_; }  // in order
  int64_t rollbacks() const { return rollbacks_; }                    // times take_rollback asked to go back

 private:
  std::set<WorkerId> refused_;
  std::vector<Refusal> refusals_;
  std::map<WorkerId, uint64_t> unchecked_since_;
  std::optional<uint64_t> rollback_from_;
  int64_t rollbacks_ = 0;
};

}  // namespace poet
