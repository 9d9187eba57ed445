#pragma once
// A batch's results by task: which are in, who answered each, and which are final — reported to the caller, never
// to change. A result from a worker whose answers may still be found wrong is held back until the batch is whole;
// if that worker is found wrong first, its results not yet final are withdrawn and the tasks computed again.

#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"
#include "simulation/rollout.h"

namespace poet {

class BatchResults {
 public:
  using Range = std::pair<size_t, size_t>;  // tasks [first, end)

  void start(size_t tasks);  // a new batch of this many tasks, none in
  void clear();
  bool has(size_t task) const { return have_[task]; }
  size_t remaining() const { return remaining_; }  // tasks without a result
  // The results of tasks [first, first + results.size()), answered by `from`: final at once, or held back.
  void put(size_t first, std::span<const RolloutResult> results, const WorkerId& from, bool final_now);
  // The results `from` gave that are not final yet are withdrawn: the ranges of tasks to compute again, in order.
  std::vector<Range> withdraw(const WorkerId& from);
  // Who answered a task (empty: no result), and whether its result is final.
  const WorkerId& from(size_t task) const { return from_[task]; }
  bool is_final(size_t task) const { return final_[task]; }
  // The tasks of [first, end) without a result, as ranges of at most `most` tasks, in order.
  std::vector<Range> missing(size_t first, size_t end, size_t most) const;
  // Whose answer the results of tasks [first, end) are, and whether final, when they are one answer's, whole.
  struct Answer {
    WorkerId from;
    bool final = false;
  };
  std::optional<Answer> one_answer(size_t first, size_t end) const;
  // Tasks [first, end), each with a result not final, are without one again: their answer is disputed.
  void reopen(size_t first, size_t end);
  // The results that became final since the last call, each range's first task and its results; with `whole` (the
  // batch is done), every result held back becomes final first.
  struct Ready {
    size_t first = 0;
    std::vector<RolloutResult> results;
  };
  std::vector<Ready> take_ready(bool whole);
  std::span<const RolloutResult> results(size_t first, size_t end) const {
    return std::span<const RolloutResult>(results_).subspan(first, end - first);
  }
  std::vector<RolloutResult> take();  // the results in task order; the batch is cleared

 private:
  std::vector<RolloutResult> results_;
  std::vector<bool> have_;
  std::vector<WorkerId> from_;  // who answered each task (empty: no result yet)
  std::vector<bool> final_;     // in a ready range already
  size_t remaining_ = 0;
  std::vector<Range> ready_;

  void unset(size_t task);  // no result any more
};

}  // namespace poet
