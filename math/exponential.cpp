#include "math/exponential.h"

#include <bit>
#include <cstdint>
#include <limits>

#include "math/tables.h"

namespace poet::math {
namespace {

using namespace tables;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 2^e as a double, for the exponents of normal numbers (−1022 ≤ e ≤ 1023).
inline double power_of_two(int64_t e) { return std::bit_cast<double>(static_cast<uint64_t>(e + 1023) << 52); }

// Adding this rounds a double of magnitude below 2^51 to an integer in the low bits of the sum: round to nearest
// (ties to even) by the addition itself, the same on every IEEE machine and with no rounding instruction.
constexpr double kRoundShift = 0x1.8p52;

// e^x = 2^e·t: x = n·ln2/128 + r with |r| ≤ ln2/256, e^x = 2^(n/128)·e^r, 2^(n/128) = 2^(n>>7)·2^((n&127)/128);
// t = 2^((n&127)/128)·e^r in [0.99, 2.01), e = n>>7. For |x| < 2^51·ln2/128.
inline double exp_mantissa(double x, int64_t& e) {
  const double shifted = x * k128OverLn2 + kRoundShift;
  const double kd = shifted - kRoundShift;
  const int64_t n = static_cast<int64_t>(std::bit_cast<uint64_t>(shifted) << 13) >> 13;  // the low 51 bits, signed
  const double r = (x - kd * kLn2Over128Hi) - kd * kLn2Over128Lo;
  // e^r − 1 by its series to r^5/120: the first left term is below 2^−60 of the result for |r| ≤ ln2/256
  const double p = r + r * r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0))));
  const int64_t j = n & 127;
  e = n >> 7;  // floor(n/128)
  return kExp2Hi[j] + (kExp2Lo[j] + kExp2Hi[j] * p);
}

// e^x where |x| ≥ 708 or x is not finite: the results near overflow, the subnormal ones, ∞, 0 and NaN.
double exp_edges(double x) {
  // beyond these e^x is +∞ or rounds to 0 (and NaN stays NaN through the comparisons' false branches)
  if (!(x <= 0x1.62e42fefa39efp+9)) return x != x ? x : kInfinity;  // ln(DBL_MAX), rounded down
  if (x < -0x1.74910d52d3052p+9) return 0.0;                        // ln of half the smallest subnormal
  int64_t e = 0;
  const double t = exp_mantissa(x, e);
  // near overflow n may round up to 2^10·128; subnormal results take two scalings, the second rounding once
  if (e > 1023) return (t * power_of_two(e - 1)) * 2.0;
  if (e >= -1021) return t * power_of_two(e);
  return (t * power_of_two(e + 1000)) * power_of_two(-1000);
}

}  // namespace

double exp(double x) {
  // |x| < 708: the result is a normal number, 2^e·t with −1022 ≤ e ≤ 1021, one exact scaling
  if ((std::bit_cast<uint64_t>(x) & 0x7fffffffffffffffull) >= std::bit_cast<uint64_t>(708.0)) return exp_edges(x);
  int64_t e = 0;
  const double t = exp_mantissa(x, e);
  return t * power_of_two(e);
}

double log(double x) {
  if (!(x > 0.0)) return x == 0.0 ? -kInfinity : kNaN;  // negative and NaN
  if (x == kInfinity) return x;
  uint64_t bits = std::bit_cast<uint64_t>(x);
  int64_t e = 0;
  if (bits < (uint64_t{1} << 52)) {  // subnormal: scale to normal first
    bits = std::bit_cast<uint64_t>(x * 0x1p54);
    e = -54;
  }
  // x = 2^e·m with m in [√2/2, √2): the biased exponent of m is 1022 or 1023
  const uint64_t mantissa = bits & ((uint64_t{1} << 52) - 1);
  const bool high = mantissa >= 0x6a09e667f3bcdull;  // m ≥ √2 before adjusting: take m/2
  e += static_cast<int64_t>(bits >> 52) - 1023 + (high ? 1 : 0);
  const double m = std::bit_cast<double>(mantissa | ((high ? uint64_t{1022} : uint64_t{1023}) << 52));
  // ln m = ln(1 + f) = 2·atanh(s), s = f/(2 + f), |s| ≤ 0.1716; written (as fdlibm does) so that the large terms
  // are exact: ln(1 + f) = f − (f²/2 − s·(f²/2 + R)), R = Σ 2·s^(2k)/(2k+1) for k ≥ 1, to s^22 (below 2^−60)
  const double f = m - 1.0;
  const double s = f / (2.0 + f);
  const double z = s * s;
  const double R =
      z *
      (2.0 / 3 +
       z * (2.0 / 5 +
            z * (2.0 / 7 +
                 z * (2.0 / 9 + z * (2.0 / 11 +
                                     z * (2.0 / 13 +
                                          z * (2.0 / 15 +
                                               z * (2.0 / 17 + z * (2.0 / 19 + z * (2.0 / 21 + z * (2.0 / 23)))))))))));
  const double half_f2 = 0.5 * f * f;
  const double ed = static_cast<double>(e);
  return ed * kLn2Hi - ((half_f2 - (s * (half_f2 + R) + ed * kLn2Lo)) - f);
}

double power(double base, uint64_t n) {
  if (n == 0) return 1.0;
  return exp(static_cast<double>(n) * log(base));
}

}  // namespace poet::math
