#pragma once
// A limit on log lines of one kind, so that a flood of peers (thousands of Hellos, frames of garbage) cannot
// flood the log: at most `per_second` lines a second, and the next line logged says how many were held back.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

namespace poet {

class LogThrottle {
 public:
  explicit LogThrottle(int per_second = 1) : per_second_(per_second) {}

  // nullopt: hold this line back. Otherwise log it, with held_back_note() of the value returned.
  std::optional<int64_t> admit(int64_t now_ms) {
    if (now_ms - window_start_ >= 1000) {
      window_start_ = now_ms;
      used_ = 0;
    }
    if (used_ >= per_second_) {
      ++held_back_;
      return std::nullopt;
    }
    ++used_;
    return std::exchange(held_back_, 0);
  }

  // " (N similar lines held back)", or nothing.
  static std::string held_back_note(int64_t held_back) {
    return held_back > 0 ? " (" + std::to_string(held_back) + " similar lines held back)" : "";
  }

 private:
  int per_second_;
  int64_t window_start_ = INT64_MIN / 2;
  int used_ = 0;
  int64_t held_back_ = 0;
};

}  // namespace poet
