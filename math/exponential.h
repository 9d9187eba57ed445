#pragma once
// exp, log, tanh and integer powers computed by the project, not the C library: plain IEEE double arithmetic (no
// FMA, no table or instruction whose result depends on the processor), so every machine and C library gets the
// same bits. Accuracy against the C library is stated in math/README.md and checked by
// tests/unit/math/exponential_test.cpp.

#include <bit>
#include <cstdint>

namespace poet::math {

// e^x; +∞ above the overflow threshold, 0 (through the subnormals) below the underflow one, NaN for NaN.
double exp(double x);

// ln x for x > 0; −∞ for ±0, NaN for x < 0 and NaN, +∞ for +∞.
double log(double x);

// tanh x, as sign(x)·(1 − e)/(1 + e) with e = exp(−2|x|): never overflows, and tanh(±0) = ±0. Inline: the
// policy takes 84 a step.
inline double tanh(double x) {
  const double e = exp(-2.0 * (x < 0.0 ? -x : x));
  const double t = (1.0 - e) / (1.0 + e);
  return std::bit_cast<double>(std::bit_cast<uint64_t>(t) | (std::bit_cast<uint64_t>(x) & (uint64_t{1} << 63)));
}

// base^n for base > 0 and an integer n ≥ 0 (the optimiser's β^t), as exp(n·ln base); 1 for n = 0.
double power(double base, uint64_t n);

}  // namespace poet::math
