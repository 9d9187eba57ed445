#pragma once
// The seam between the algorithm and where rollouts run: a batch of tasks in, their results out in task order.
// The POET loop never knows whether a batch ran on threads in this process or on workers elsewhere.

#include <span>
#include <stdexcept>
#include <vector>

#include "rollout_task.h"

namespace poet {

// Thrown by evaluate() when a stop was requested (its evaluator's stop token) before the batch completed: the
// batch is abandoned and none of its results exist.
class EvaluationStopped : public std::runtime_error {
 public:
  EvaluationStopped() : std::runtime_error("evaluation stopped on request") {}
};

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  // Runs every task once; result i belongs to task i. Blocks until the whole batch is done. Throws when a task
  // cannot be run at all (the run stops there; its last checkpoint stays valid), and EvaluationStopped when a stop
  // is requested before the batch completes; an evaluator honours a stop request within about a second.
  virtual std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) = 0;
};

}  // namespace poet
