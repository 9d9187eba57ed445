#pragma once
// The seam between the algorithm and where rollouts run: a batch of tasks in, their results out in task order.
// The POET loop never knows whether a batch ran on threads in this process or on workers elsewhere.

#include <cstddef>
#include <functional>
#include <span>
#include <stdexcept>
#include <vector>

#include "simulation/rollout_task.h"

namespace poet {

// Thrown by evaluate() when a stop was requested (its evaluator's stop token) before the batch completed: the
// batch is abandoned and none of its results exist.
class EvaluationStopped : public std::runtime_error {
 public:
  EvaluationStopped() : std::runtime_error("evaluation stopped on request") {}
};

// Results [first, first + results.size()) of the batch are final: evaluate() will return exactly these. Called
// zero or more times before evaluate() returns, each index at most once, from any of the evaluator's threads
// but never concurrently with itself; it runs on the evaluator's dispatch path, so it must be quick. An empty
// function means nobody listens.
using ResultsReady = std::function<void(size_t first, std::span<const RolloutResult> results)>;

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  // Runs every task once; result i belongs to task i. Blocks until the whole batch is done, telling `ready` about
  // results as they become final (so the caller can start on them early). Throws when a task cannot be run at all
  // (the run stops there; its last checkpoint stays valid), and EvaluationStopped when a stop is requested before
  // the batch completes; an evaluator honours a stop request within about a second.
  virtual std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) = 0;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) { return evaluate(tasks, {}); }
};

}  // namespace poet
