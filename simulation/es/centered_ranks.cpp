#include "simulation/es/centered_ranks.h"

#include <algorithm>
#include <numeric>

namespace poet {

std::vector<double> centered_ranks(std::span<const double> returns) {
  const size_t n = returns.size();
  std::vector<double> out(n, 0.0);
  if (n < 2) return out;  // rank/(n − 1) is undefined for one return; its centre is 0
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  // Stable: equal returns keep index order, so ties get ranks deterministically (not numpy's unstable argsort).
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return returns[a] < returns[b]; });
  const double denominator = static_cast<double>(n - 1);
  for (size_t rank = 0; rank < n; ++rank) out[order[rank]] = static_cast<double>(rank) / denominator - 0.5;
  return out;
}

}  // namespace poet
