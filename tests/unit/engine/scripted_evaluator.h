#pragma once
// A fake Evaluator for the engine's logic tests: every result comes from a script (call number, index in the
// batch, task), and every batch is recorded so a test can see what the loop asked for.

#include <functional>
#include <vector>

#include "engine/evaluator.h"

namespace poet::testing {

class ScriptedEvaluator final : public Evaluator {
 public:
  using Script = std::function<RolloutResult(int call, size_t index, const RolloutTask& task)>;
  explicit ScriptedEvaluator(Script script) : script_(std::move(script)) {}

  using Evaluator::evaluate;
  // Reports the whole batch final before returning it, so the engine's early ES outcomes run in every test.
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    const int call = static_cast<int>(batches.size());
    batches.emplace_back(tasks.begin(), tasks.end());
    std::vector<RolloutResult> out;
    for (size_t i = 0; i < tasks.size(); ++i) out.push_back(script_(call, i, tasks[i]));
    if (ready) ready(0, out);
    return out;
  }

  std::vector<std::vector<RolloutTask>> batches;  // every batch, in call order

 private:
  Script script_;
};

// A result with this return; finished when it reaches 230 (the solved score), 10 steps.
inline RolloutResult scored(double total_reward, bool finished = false) {
  RolloutResult r;
  r.total_reward = total_reward;
  r.steps = 10;
  r.finished = finished;
  return r;
}

}  // namespace poet::testing
