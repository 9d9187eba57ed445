#pragma once
// An Evaluator that runs a batch on N threads of this process: the embedded default and the tests' evaluator.
// Results do not depend on the thread count: every task is a pure function of its contents.

#include "evaluator/evaluator.h"

namespace poet {

class LocalEvaluator final : public Evaluator {
 public:
  explicit LocalEvaluator(int threads) : threads_(threads < 1 ? 1 : threads) {}
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) override;
  int threads() const { return threads_; }

 private:
  int threads_;
};

}  // namespace poet
