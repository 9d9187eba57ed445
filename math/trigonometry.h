#pragma once
// Sine and cosine computed by the project, not the C library: plain IEEE double arithmetic (no FMA, no table or
// instruction whose result depends on the processor), so every machine and C library gets the same bits.
// Accuracy against the C library is stated in math/README.md and checked by tests/unit/math/trigonometry_test.cpp.

namespace poet::math {

struct SinCos {
  double sin;
  double cos;
};

// Finite x of any size (the reduction by π/2 is exact enough for every double); NaN for ±∞ and NaN.
double sin(double x);
double cos(double x);
// Both from one reduction: the same bits as sin(x) and cos(x).
SinCos sincos(double x);

// Single precision, for Box2D's rotations: the double functions rounded once to float (but for about 1 in 10^4
// arguments, where a shorter series' error flips the rounding). sincos: both from one reduction, the same bits.
struct SinCosF {
  float sin;
  float cos;
};
float sin(float x);
float cos(float x);
SinCosF sincos(float x);

}  // namespace poet::math
