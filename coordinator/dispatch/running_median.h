#pragma once
// The median of the values added so far, in O(log n) an addition: the upper median (the value at index n / 2 of
// the sorted values) of the jobs' times a batch has seen, which the dispatcher reads after every result. Two heaps;
// the standard library has no running order statistic.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

namespace poet {

class RunningMedian {
 public:
  void add(int64_t value) {
    if (!upper_.empty() && value < upper_.top()) {
      lower_.push(value);
    } else {
      upper_.push(value);
    }
    // upper_ holds the largest n - n / 2 values, so its least is the one at index n / 2
    const size_t n = lower_.size() + upper_.size();
    while (upper_.size() > n - n / 2) {
      lower_.push(upper_.top());
      upper_.pop();
    }
    while (upper_.size() < n - n / 2) {
      upper_.push(lower_.top());
      lower_.pop();
    }
  }
  bool empty() const { return upper_.empty(); }
  int64_t median() const { return upper_.top(); }  // not empty
  void clear() {
    lower_ = {};
    upper_ = {};
  }

 private:
  std::priority_queue<int64_t> lower_;                                               // the smallest n / 2
  std::priority_queue<int64_t, std::vector<int64_t>, std::greater<int64_t>> upper_;  // the rest
};

}  // namespace poet
