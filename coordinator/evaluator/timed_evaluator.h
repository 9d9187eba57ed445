#pragma once
// An Evaluator in front of another that counts the seconds its callers spend in evaluate(): the time the run loop
// waits for rollouts (with local threads, also the share it runs itself), set against the rest of an iteration —
// the coordinator's own serial work (wall_times.csv's waiting_s). The clock is a parameter, so tests drive it.

#include <functional>
#include <utility>

#include "engine/evaluator.h"

namespace poet {

class TimedEvaluator final : public Evaluator {
 public:
  // now: seconds on a monotonic clock.
  TimedEvaluator(Evaluator& inner, std::function<double()> now) : inner_(inner), now_(std::move(now)) {}
  using Evaluator::evaluate;

  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    const double began = now_();
    try {
      std::vector<RolloutResult> results = inner_.evaluate(tasks, ready);
      seconds_ += now_() - began;
      return results;
    } catch (...) {  // a stop or a failure: the time was spent waiting all the same
      seconds_ += now_() - began;
      throw;
    }
  }

  Withdrawals withdrawals() override { return inner_.withdrawals(); }
  void went_back(uint64_t last_batch) override { inner_.went_back(last_batch); }

  // The seconds spent in evaluate() since the last take (or the start), and a fresh count.
  double take() { return std::exchange(seconds_, 0.0); }

 private:
  Evaluator& inner_;
  std::function<double()> now_;
  double seconds_ = 0;
};

}  // namespace poet
