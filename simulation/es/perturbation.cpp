#include "simulation/es/perturbation.h"

#include <cmath>
#include <stdexcept>

#include "math/exponential.h"
#include "math/trigonometry.h"
#include "simulation/rng.h"

namespace poet {
namespace {

constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

// Box–Muller on the j-th pair of draws of a stream: both the cosine and the sine half are used, so one log, one
// sqrt and one sincos give two normals (half the cost of RandomStream::normal() per value). The cosine half is
// exactly what RandomStream::normal() would return for the same two draws.
struct NormalPair {
  double even;  // element 2j
  double odd;   // element 2j + 1
};

inline NormalPair normal_pair(RandomStream& rng) {
  const double u1 = 1.0 - rng.uniform01();  // (0, 1]: log is finite
  const double u2 = rng.uniform01();
  const double r = std::sqrt(-2.0 * math::log(u1));
  const math::SinCos angle = math::sincos(kTwoPi * u2);
  return {r * angle.cos, r * angle.sin};
}

// Calls f(i, ε_i) for i = 0..n−1 in order. Pair j consumes draws 2j+1 and 2j+2 of RandomStream(key), whatever n
// is, which gives the prefix property; an odd n drops the sine half of the last pair.
template <typename F>
inline void for_each_normal(uint64_t key, size_t n, F&& f) {
  RandomStream rng(key);
  size_t i = 0;
  for (; i + 1 < n; i += 2) {
    const NormalPair z = normal_pair(rng);
    f(i, z.even);
    f(i + 1, z.odd);
  }
  if (i < n) f(i, normal_pair(rng).even);
}

}  // namespace

void fill_perturbation(uint64_t key, std::span<double> out) {
  for_each_normal(key, out.size(), [&](size_t i, double z) { out[i] = z; });
}

std::vector<double> perturbation(uint64_t key, size_t n) {
  std::vector<double> out(n);
  fill_perturbation(key, out);
  return out;
}

void perturb(std::span<const double> theta, uint64_t key, int sign, double sigma, std::span<double> out) {
  if (theta.size() != out.size()) throw std::invalid_argument("perturb: theta and out differ in size");
  if (sign != 1 && sign != -1) throw std::invalid_argument("perturb: sign must be +1 or -1");
  const double scale = sign * sigma;
  // out[i] is written after theta[i] is read and no other element is touched, so out may alias theta.
  for_each_normal(key, out.size(), [&](size_t i, double z) { out[i] = theta[i] + scale * z; });
}

}  // namespace poet
