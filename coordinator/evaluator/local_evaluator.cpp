#include "evaluator/local_evaluator.h"

#include "parallel_for.h"

namespace poet {

std::vector<RolloutResult> LocalEvaluator::evaluate(std::span<const RolloutTask> tasks) {
  std::vector<RolloutResult> results(tasks.size());
  parallel_for(static_cast<int>(tasks.size()), threads_, [&](int i) { results[i] = run_task(tasks[i]); });
  return results;
}

}  // namespace poet
