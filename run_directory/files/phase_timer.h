#pragma once
// Where an iteration's time goes: the seconds of each of its phases (poet/phase_observer.h), measured on a clock
// given as a function so that tests can drive it. Time outside any phase (between iterations: saving, logging) is
// not counted. Not thread-safe: the run loop's thread announces the phases and takes the totals.

#include <functional>
#include <optional>

#include "engine/phase_observer.h"
#include "run_directory/files/wall_times.h"

namespace poet {

class PhaseTimer : public PhaseObserver {
 public:
  // now: seconds on a monotonic clock.
  explicit PhaseTimer(std::function<double()> now) : now_(std::move(now)) {}

  void phase_begins(IterationPhase phase) override;
  void iteration_ends() override;

  // The seconds of each phase since the last take (or the start), and a fresh count.
  PhaseSeconds take();

 private:
  void close_current();

  std::function<double()> now_;
  std::optional<IterationPhase> current_;
  double began_ = 0;
  PhaseSeconds totals_{};
};

}  // namespace poet
