#pragma once
// A one-line status on stderr, redrawn in place ('\r') after each iteration: iteration/limit, active pairs, the
// best latest score among active pairs, pairs solved, rollouts/s over the last ~10 s and the ETA to the
// iteration limit from the mean iteration wall time. Wall-clock time lives only here, never in the run files.
// Off unless stderr is a terminal (or forced), so logs redirected to a file stay clean.

#include <chrono>
#include <cstdint>
#include <deque>
#include <string>
#include <utility>

#include "engine/iteration_report.h"
#include "engine/run_state.h"

namespace poet {

class ProgressDisplay {
 public:
  using Clock = std::chrono::steady_clock;

  // enabled: draw at all (false for --quiet); force: draw even when stderr is not a terminal.
  explicit ProgressDisplay(bool enabled, bool force = false);
  ~ProgressDisplay() { finish(); }
  ProgressDisplay(const ProgressDisplay&) = delete;
  ProgressDisplay& operator=(const ProgressDisplay&) = delete;

  bool enabled() const { return enabled_; }

  // After an iteration: records its rollouts and wall time, then redraws the line.
  void update(const RunState& state, const IterationReport& report);

  // Erases the line so a log message can be printed; the next update draws it again.
  void clear();

  // Ends the line (a newline), leaving the last status on screen.
  void finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_;
  int iterations_ = 0;                                        // iterations done since start_
  int64_t rollouts_total_ = 0;                                // rollouts since start_
  std::deque<std::pair<Clock::time_point, int64_t>> window_;  // (time, rollouts_total_) over the last ~10 s
};

// The status text (no '\r'), from the state and the rates; exposed for the coordinator's summary and tests.
// rollouts_per_second < 0 or eta_seconds < 0: unknown yet.
std::string progress_line(const RunState& state, double rollouts_per_second, double eta_seconds);

}  // namespace poet
