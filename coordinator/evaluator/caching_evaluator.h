#pragma once
// An Evaluator in front of another that runs no episode twice. A rollout is a pure function of its task (θ, course
// and terrain seed, episode settings: run_task), so an unperturbed task seen before has the result it had, and a
// task repeated within a batch runs once. The loop asks again for scores it knows — a pair's θ on its own course
// in a transfer round right after its evaluation, a parent's θ on a child in the admission walk after the minimal
// criterion, archived θs on archived courses in Enhanced POET's PATA-EC — and gets them from here. Perturbed tasks
// (an ES step's θ ± σε, never repeated) pass through unseen. Bounded in memory: beyond max_bytes (keys, results and
// the maps' own share, estimated) the oldest go first.
// Kept in memory only: a resumed run starts with it empty and computes those episodes again, to the same numbers;
// the run's counters count every rollout the loop asked for, cached or not, so a run is the same with or without it.

#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>

#include "engine/evaluator.h"

namespace poet {

// The coordinator's bound: some 200,000 results of obstacle courses (a key is about 100 bytes), fewer of CPPN
// terrains (their genome is in the key).
inline constexpr size_t kScoreCacheBytes = size_t{64} << 20;

class CachingEvaluator final : public Evaluator {
 public:
  CachingEvaluator(Evaluator& inner, size_t max_bytes) : inner_(inner), max_bytes_(max_bytes) {}
  using Evaluator::evaluate;
  // The inner evaluator runs the tasks not known (each distinct one once), in task order; known results are
  // reported to `ready` first, then the inner evaluator's as they come, each index once.
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override;
  // The inner evaluator's: the cache withdraws nothing of its own.
  Withdrawals withdrawals() override { return inner_.withdrawals(); }
  // Forgets every result (the wrong worker's may be among them), and tells the inner evaluator.
  void went_back(uint64_t last_batch) override;
  // Forgets every result.
  void clear();

  int64_t episodes_saved() const { return episodes_saved_; }  // tasks answered without running them
  int64_t steps_saved() const { return steps_saved_; }        // their environment steps
  size_t size() const { return results_.size(); }
  size_t bytes() const { return bytes_; }

 private:
  void remember(std::string key, const RolloutResult& result);

  Evaluator& inner_;
  static size_t cost(const std::string& key) { return 2 * key.size() + sizeof(RolloutResult) + 96; }

  size_t max_bytes_;
  size_t bytes_ = 0;
  std::unordered_map<std::string, RolloutResult> results_;  // by the task's wire form (θ named by its hash)
  std::deque<std::string> order_;                           // keys, oldest first
  int64_t episodes_saved_ = 0;
  int64_t steps_saved_ = 0;
};

}  // namespace poet
