#pragma once
// The seam between the algorithm and where rollouts run: a batch of tasks in, their results out in task order.
// The POET loop never knows whether a batch ran on threads in this process or on workers elsewhere.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
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
// zero or more times before evaluate() returns, each index at most once, from the thread that called evaluate() or
// one of the evaluator's own, never concurrently with itself and never under a lock the evaluator needs to go on
// (the remote evaluator calls it on evaluate()'s thread while its socket thread keeps serving). The batch's end
// waits for it, so it should be quick: the engine hands its gradient work to threads of its own. An empty function
// means nobody listens.
using ResultsReady = std::function<void(size_t first, std::span<const RolloutResult> results)>;

// Results an evaluator may take back after evaluate() returned them: with verification, a remote worker's unchecked
// answers are final once their batch is whole, and the worker found wrong later makes them wrong. Batches are
// numbered from 1 as evaluate() starts them. A caller keeps a state from before each batch in `reachable`; told
// `withdrawn_from`, it goes back to a state from before that batch and says so (Evaluator::went_back).
struct Withdrawals {
  bool possible = false;                   // whether results may ever be withdrawn (false: the rest stays empty)
  uint64_t last_batch = 0;                 // the batch started last (0: none yet)
  std::optional<uint64_t> withdrawn_from;  // results of this batch and later ones may be wrong: go back before it
  std::vector<uint64_t> reachable;         // batches whose results may yet be withdrawn
};

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  // Runs every task once; result i belongs to task i. Blocks until the whole batch is done, telling `ready` about
  // results as they become final (so the caller can start on them early). Throws when a task cannot be run at all
  // (the run stops there; its last checkpoint stays valid), and EvaluationStopped when a stop is requested before
  // the batch completes; an evaluator honours a stop request within about a second.
  virtual std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) = 0;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) { return evaluate(tasks, {}); }

  // Which of its results are withdrawn, or may yet be; a withdrawal stands until went_back. Called between batches.
  // By default none ever is.
  virtual Withdrawals withdrawals() { return {}; }
  // The caller went back to a state saved when `last_batch` was the batch started last: the results of later
  // batches count no more, and an evaluator that remembers results forgets them.
  virtual void went_back(uint64_t /*last_batch*/) {}
};

}  // namespace poet
