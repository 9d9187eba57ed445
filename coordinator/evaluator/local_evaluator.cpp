#include "evaluator/local_evaluator.h"

#include "parallel_for.h"

namespace poet {

std::vector<RolloutResult> LocalEvaluator::evaluate(std::span<const RolloutTask> tasks) {
  std::vector<RolloutResult> results(tasks.size());
  parallel_for(static_cast<int>(tasks.size()), threads_, [&](int i) {
    if (stop_.stop_requested()) throw EvaluationStopped();
    results[i] = run_task(tasks[i], stop_);
  });
  // an episode cut short by the stop is not a result: the whole batch goes
  if (stop_.stop_requested()) throw EvaluationStopped();
  return results;
}

}  // namespace poet
