#pragma once
// The seam between the algorithm and where rollouts run: a batch of tasks in, their results out in task order.
// The POET loop never knows whether a batch ran on threads in this process or on workers elsewhere.

#include <span>
#include <vector>

#include "rollout_task.h"

namespace poet {

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  // Runs every task once; result i belongs to task i. Blocks until the whole batch is done. Throws when a task
  // cannot be run at all (the run stops there; its last checkpoint stays valid).
  virtual std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) = 0;
};

}  // namespace poet
