#include "coordinator/evaluator/local_evaluator.h"

#include <mutex>

#include "simulation/parallel_for.h"

namespace poet {

std::vector<RolloutResult> LocalEvaluator::evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) {
  std::vector<RolloutResult> results(tasks.size());
  std::mutex ready_mutex;  // the listener is never called concurrently with itself
  parallel_for(static_cast<int>(tasks.size()), threads_, [&](int i) {
    if (stop_.stop_requested()) throw EvaluationStopped();
    const size_t index = static_cast<size_t>(i);
    results[index] = run_task(tasks[index], stop_);
    if (!ready || results[index].stopped) return;  // an episode cut short is not final
    std::lock_guard lock(ready_mutex);
    ready(index, std::span(&results[index], 1));
  });
  // an episode cut short by the stop is not a result: the whole batch goes
  if (stop_.stop_requested()) throw EvaluationStopped();
  return results;
}

}  // namespace poet
