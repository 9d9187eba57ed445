#include "run_directory/files/phase_timer.h"

namespace poet {

void PhaseTimer::close_current() {
  if (!current_) return;
  totals_[static_cast<size_t>(*current_)] += now_() - began_;
  current_.reset();
}

void PhaseTimer::phase_begins(IterationPhase phase) {
  close_current();
  current_ = phase;
  began_ = now_();
}

void PhaseTimer::iteration_ends() { close_current(); }

PhaseSeconds PhaseTimer::take() {
  const PhaseSeconds out = totals_;
  totals_ = {};
  return out;
}

}  // namespace poet
