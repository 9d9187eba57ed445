#pragma once
// Distances in units in the last place, and the inputs the accuracy tests draw.

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "simulation/rng.h"

namespace poet::math_test {

// How many doubles lie between a and b (0 when equal, both NaN, or ±0); ordered so that it counts across zero.
inline uint64_t ulps_apart(double a, double b) {
  if (a == b || (std::isnan(a) && std::isnan(b))) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint64_t>::max();
  const auto ordered = [](double x) {
    const int64_t i = std::bit_cast<int64_t>(x);
    return i < 0 ? std::numeric_limits<int64_t>::min() - i : i;
  };
  const int64_t ia = ordered(a);
  const int64_t ib = ordered(b);
  return ia > ib ? static_cast<uint64_t>(ia) - static_cast<uint64_t>(ib)
                 : static_cast<uint64_t>(ib) - static_cast<uint64_t>(ia);
}

inline uint64_t ulps_apart(float a, float b) {
  if (a == b || (std::isnan(a) && std::isnan(b))) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint64_t>::max();
  const auto ordered = [](float x) {
    const int32_t i = std::bit_cast<int32_t>(x);
    return i < 0 ? static_cast<int64_t>(std::numeric_limits<int32_t>::min()) - i : static_cast<int64_t>(i);
  };
  const int64_t d = ordered(a) - ordered(b);
  return static_cast<uint64_t>(d < 0 ? -d : d);
}

// The largest distance of f from g over n inputs drawn uniformly from [lo, hi) by stream `purpose`, and where.
struct Worst {
  uint64_t ulps = 0;
  double at = 0.0;
};

template <typename F, typename G>
Worst worst_over(F f, G g, double lo, double hi, int n, std::string_view purpose) {
  RandomStream rng(stream_key(7, purpose));
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const double x = rng.uniform(lo, hi);
    const uint64_t d = ulps_apart(f(x), g(x));
    if (d > worst.ulps) worst = {d, x};
  }
  return worst;
}

}  // namespace poet::math_test
