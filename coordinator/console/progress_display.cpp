#include "coordinator/console/progress_display.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace poet {
namespace {

constexpr auto kRateWindow = std::chrono::seconds(10);

std::string duration_text(double seconds) {
  const auto s = static_cast<int64_t>(std::llround(seconds));
  char buffer[48];
  if (s >= 3600)
    std::snprintf(buffer, sizeof buffer, "%lldh%02lldm", static_cast<long long>(s / 3600),
                  static_cast<long long>(s / 60 % 60));
  else if (s >= 60)
    std::snprintf(buffer, sizeof buffer, "%lldm%02llds", static_cast<long long>(s / 60),
                  static_cast<long long>(s % 60));
  else
    std::snprintf(buffer, sizeof buffer, "%llds", static_cast<long long>(s));
  return buffer;
}

}  // namespace

std::string progress_line(const RunState& state, double rollouts_per_second, double eta_seconds) {
  int active = 0;
  int solved = 0;
  double best = -std::numeric_limits<double>::infinity();
  for (const Pair& pair : state.pairs) {
    if (pair.solved()) ++solved;
    if (!pair.active()) continue;
    ++active;
    best = std::max(best, pair.latest_score);
  }
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "iteration %d/%d | pairs %d | best %.1f | solved %d", state.next_iteration,
                state.settings.iterations, active, active > 0 ? best : 0.0, solved);
  std::string line = buffer;
  if (rollouts_per_second >= 0) {
    std::snprintf(buffer, sizeof buffer, " | %.0f rollouts/s", rollouts_per_second);
    line += buffer;
  }
  if (eta_seconds >= 0) line += " | ETA " + duration_text(eta_seconds);
  return line;
}

ProgressDisplay::ProgressDisplay(bool enabled, bool force)
    : enabled_(enabled && (force || ::isatty(STDERR_FILENO) == 1)), start_(Clock::now()) {
  window_.emplace_back(start_, 0);
}

void ProgressDisplay::update(const RunState& state, const IterationReport& report) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  ++iterations_;
  rollouts_total_ += report.rollouts;
  window_.emplace_back(now, rollouts_total_);
  // keep one sample at or before the window's start, so the rate always spans ~10 s once the run is that old
  while (window_.size() > 2 && window_[1].first <= now - kRateWindow) window_.pop_front();

  const double window_seconds = std::chrono::duration<double>(now - window_.front().first).count();
  const double rate =
      window_seconds > 0 ? static_cast<double>(rollouts_total_ - window_.front().second) / window_seconds : -1;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const int remaining = state.settings.iterations - state.next_iteration;
  const double eta = remaining > 0 ? elapsed / iterations_ * remaining : 0;

  std::fprintf(stderr, "\r%s\033[K", progress_line(state, rate, eta).c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressDisplay::clear() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

void ProgressDisplay::finish() {
  if (!drawn_) return;
  std::fputs("\n", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace poet
