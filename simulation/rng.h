#pragma once
// The project's deterministic random numbers. Every draw is a pure function of (key, counter), so a stream is
// reproducible from a small seed on any machine or process, and its whole state is two integers. The
// distributions are defined here (not by the standard library, whose distributions differ between
// implementations); normal() takes its logarithm and cosine from the project's math (math/), and std::sqrt,
// which IEEE 754 rounds correctly everywhere.

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string_view>

#include "math/exponential.h"
#include "math/trigonometry.h"

namespace poet {

inline constexpr uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ULL;

__extension__ using uint128 = unsigned __int128;  // GCC and Clang both have it; -Wpedantic knows it is not ISO

// SplitMix64's output function: a bijective 64-bit mixer that passes BigCrush when fed a Weyl sequence.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// FNV-1a, to turn a purpose name ("terrain", "noise") into part of a key.
constexpr uint64_t hash_name(std::string_view name) {
  uint64_t h = 0xCBF29CE484222325ULL;
  for (char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001B3ULL;
  }
  return h;
}

// The key of the stream for (seed, purpose, ids...): e.g. (run seed, "noise", pair, step, index).
constexpr uint64_t stream_key(uint64_t seed, std::string_view purpose, std::initializer_list<uint64_t> ids = {}) {
  uint64_t k = mix64(seed + kGoldenGamma);
  k = mix64(k ^ hash_name(purpose));
  for (uint64_t id : ids) k = mix64(k ^ (id + kGoldenGamma));
  return k;
}

// A counter-based stream: draw n is mix64(key + n·γ). Copyable value; not thread-safe to share.
class RandomStream {
 public:
  explicit constexpr RandomStream(uint64_t key, uint64_t counter = 0) : key_(key), counter_(counter) {}

  constexpr uint64_t next_u64() { return mix64(key_ + (++counter_) * kGoldenGamma); }

  // Uniform in [0, 1) with 53 random bits.
  constexpr double uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  // Uniform in [lo, hi); lo when lo == hi. Requires lo <= hi.
  constexpr double uniform(double lo, double hi) {
    double x = lo + (hi - lo) * uniform01();
    return (x < hi || lo == hi) ? x : lo;  // rounding can reach hi; fold it back into the interval
  }

  // Uniform integer in [lo, hi), unbiased (Lemire's method). A one-value range consumes no draw, as numpy's
  // randint does, so the terrain's draw sequence matches the reference's. Throws if hi <= lo.
  constexpr int64_t uniform_int(int64_t lo, int64_t hi) {
    if (hi <= lo) throw std::invalid_argument("uniform_int: empty range");
    const uint64_t n = static_cast<uint64_t>(hi - lo);
    if (n == 1) return lo;
    uint128 m = static_cast<uint128>(next_u64()) * n;
    if (static_cast<uint64_t>(m) < n) {
      const uint64_t threshold = (0 - n) % n;
      while (static_cast<uint64_t>(m) < threshold) m = static_cast<uint128>(next_u64()) * n;
    }
    return lo + static_cast<int64_t>(m >> 64);
  }

  // Standard normal by Box–Muller; consumes exactly two draws.
  double normal() {
    const double u1 = 1.0 - uniform01();  // (0, 1]: log is finite
    const double u2 = uniform01();
    return std::sqrt(-2.0 * math::log(u1)) * math::cos(2.0 * 3.14159265358979323846 * u2);
  }

  constexpr uint64_t key() const { return key_; }
  constexpr uint64_t counter() const { return counter_; }

 private:
  uint64_t key_;
  uint64_t counter_;
};

}  // namespace poet
