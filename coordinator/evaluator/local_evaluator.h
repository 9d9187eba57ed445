#pragma once
// An Evaluator that runs a batch on N threads of this process: the embedded default and the tests' evaluator.
// Results do not depend on the thread count: every task is a pure function of its contents. A stop request on the
// token cuts the episodes in flight short (rollouts check it every few dozen steps) and abandons the batch.

#include <stop_token>

#include "engine/evaluator.h"

namespace poet {

class LocalEvaluator final : public Evaluator {
 public:
  explicit LocalEvaluator(int threads, std::stop_token stop = {})
      : threads_(threads < 1 ? 1 : threads), stop_(std::move(stop)) {}
  using Evaluator::evaluate;
  // Reports each task's result to `ready` as soon as its episode ends (one index per call).
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override;
  int threads() const { return threads_; }

 private:
  int threads_;
  std::stop_token stop_;
};

}  // namespace poet
