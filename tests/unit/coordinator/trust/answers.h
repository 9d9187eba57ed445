#pragma once
// An answer's results for trust's tests: `count` episodes returning `total` each, 100 steps long.

#include <cstddef>
#include <vector>

#include "simulation/rollout.h"

namespace poet::testing {

inline std::vector<RolloutResult> returns(double total, size_t count = 2) {
  RolloutResult r;
  r.total_reward = total;
  r.steps = 100;
  return std::vector<RolloutResult>(count, r);
}

}  // namespace poet::testing
