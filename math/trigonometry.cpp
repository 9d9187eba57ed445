#include "math/trigonometry.h"

#include <bit>
#include <cstdint>
#include <limits>

#include "math/tables.h"

namespace poet::math {
namespace {

using namespace tables;

// A reduced argument r = hi + lo, |r| ≤ π/4 (a little more at the Cody–Waite edge), and its quadrant mod 4.
struct Reduced {
  double hi;
  double lo;
  uint64_t quadrant;
};

constexpr double kRoundShift = 0x1.8p52;  // see exponential.cpp: adding it rounds to an integer

// The product a·b as hi + lo exactly (Dekker's algorithm: no FMA, so the same on every machine).
struct TwoDouble {
  double hi;
  double lo;
};
inline TwoDouble split_veltkamp(double a) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double hi = c - (c - a);
  return {hi, a - hi};
}
inline TwoDouble two_product(double a, double b) {
  const double p = a * b;
  const TwoDouble as = split_veltkamp(a);
  const TwoDouble bs = split_veltkamp(b);
  const double err = ((as.hi * bs.hi - p) + as.hi * bs.lo + as.lo * bs.hi) + as.lo * bs.lo;
  return {p, err};
}

// |x| < 2^20·π/2: k = round(x·2/π), r = x − k·π/2 with π/2 in three 33-bit parts (each k·part exact) and a fourth.
inline Reduced reduce_medium(double x) {
  const double kd = (x * kTwoOverPi + kRoundShift) - kRoundShift;
  const double r1 = x - kd * kPiOver2Part1;  // exact: the two are close (Sterbenz) or k = 0
  const double w2 = kd * kPiOver2Part2;
  const double r2 = r1 - w2;
  const double w3 = kd * kPiOver2Part3 + kd * kPiOver2Part4;
  const double hi = r2 - w3;
  // what the two roundings above lost, so that hi + lo carries about 100 bits of π/2's multiple
  const double lo = ((r1 - r2) - w2) + ((r2 - hi) - w3);
  return {hi, lo, static_cast<uint64_t>(static_cast<int64_t>(kd))};
}

// Any finite |x| ≥ 2^20·π/2 (Payne and Hanek): x = M·2^E with M an integer below 2^53; x·2/π mod 4 is M times the
// 192 bits of 2/π from bit E−1 on (bits before the point are 0; earlier bits give multiples of 4), mod 2^192.
inline Reduced reduce_large(double x) {
  const uint64_t bits = std::bit_cast<uint64_t>(x);
  const int64_t biased = static_cast<int64_t>((bits >> 52) & 0x7ff);
  const uint64_t m = (bits & ((uint64_t{1} << 52) - 1)) | (uint64_t{1} << 52);
  const int64_t e = biased - 1075;
  // the 192 bits of 2/π starting at bit position e−1 (position 1 is the first after the point)
  auto word_at = [](int64_t first) -> uint64_t {  // 64 bits from position `first`, zero before position 1
    if (first + 63 < 1) return 0;
    if (first < 1) return kTwoOverPiBits[0] >> (1 - first);
    const int64_t index = (first - 1) / 64;
    const int shift = static_cast<int>((first - 1) % 64);
    const uint64_t high = kTwoOverPiBits[index] << shift;
    return shift == 0 ? high : high | (kTwoOverPiBits[index + 1] >> (64 - shift));
  };
  const uint64_t w0 = word_at(e - 1);
  const uint64_t w1 = word_at(e - 1 + 64);
  const uint64_t w2 = word_at(e - 1 + 128);
  __extension__ typedef unsigned __int128 u128;  // GCC's, on every 64-bit target
  const u128 p2 = static_cast<u128>(m) * w2;
  const u128 p1 = static_cast<u128>(m) * w1;
  const uint64_t p0 = m * w0;  // only its low word counts, mod 2^192
  const uint64_t low = static_cast<uint64_t>(p2);
  const u128 mid_sum = (p2 >> 64) + static_cast<uint64_t>(p1);
  const uint64_t mid = static_cast<uint64_t>(mid_sum);
  const uint64_t top = static_cast<uint64_t>(p1 >> 64) + p0 + static_cast<uint64_t>(mid_sum >> 64);
  // top's two high bits are the quadrant; the 128 bits after them, read as a signed fraction in [−1/2, 1/2) of a
  // quadrant, round the quadrant to nearest
  const uint64_t f_high = (top << 2) | (mid >> 62);
  const uint64_t f_low = (mid << 2) | (low >> 62);
  const uint64_t quadrant = (top >> 62) + (f_high >> 63);
  const int64_t f_signed = static_cast<int64_t>(f_high);
  // the fraction as a double-double: the high 64 bits (rounded to 53) and what that rounding and f_low add
  const double a = static_cast<double>(f_signed >> 11) * 2048.0;  // the top 53 bits, exactly
  const int64_t a_error = f_signed & 2047;                        // the 11 below them (≥ 0: >> floors)
  const double f_hi = a * 0x1p-64;
  const double f_lo = (static_cast<double>(a_error) + static_cast<double>(f_low) * 0x1p-64) * 0x1p-64;
  // r = f·π/2 as hi + lo
  const TwoDouble product = two_product(f_hi, kPiOver2Hi);
  const double lo = product.lo + (f_hi * kPiOver2Lo + f_lo * kPiOver2Hi);
  const double hi = product.hi + lo;
  return {hi, lo - (hi - product.hi), quadrant};
}

inline Reduced reduce(double x) {
  const double ax = x < 0 ? -x : x;
  if (ax <= 0x1.921fb54442d18p-1) return {x, 0.0, 0};  // |x| ≤ π/4: nothing to reduce
  if (ax < 0x1.921fb54442d18p+20) return reduce_medium(x);
  const Reduced r = reduce_large(ax);  // sin(−x) = −sin x, cos(−x) = cos x: quadrant 4 − q, r → −r
  return x < 0 ? Reduced{-r.hi, -r.lo, 0 - r.quadrant} : r;
}

// sin(x + y) for |x| ≤ π/4 + a little, |y| tiny, by the series to x^17/17! (the next term is below 2^−60 of the
// result), written as fdlibm's kernel is so that the large terms are exact: x + ((y − x²(y/2 − x³·P)) − x³/6).
inline double kernel_sin(double x, double y) {
  const double z = x * x;
  const double v = z * x;
  const double p =
      1.0 / 120 +
      z * (-1.0 / 5040 +
           z * (1.0 / 362880 + z * (-1.0 / 39916800 + z * (1.0 / 6227020800 +
                                                           z * (-1.0 / 1307674368000 + z * (1.0 / 355687428096000))))));
  return x - ((z * (0.5 * y - v * p) - y) + v * (1.0 / 6));
}

// cos(x + y) likewise, by the series to x^16/16!: 1 − x²/2 computed as w + ((1 − w) − x²/2) so that it is exact.
inline double kernel_cos(double x, double y) {
  const double z = x * x;
  const double p =
      z * z *
      (1.0 / 24 +
       z * (-1.0 / 720 +
            z * (1.0 / 40320 + z * (-1.0 / 3628800 +
                                    z * (1.0 / 479001600 + z * (-1.0 / 87178291200 + z * (1.0 / 20922789888000)))))));
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + (p - x * y));
}

inline double sin_of(const Reduced& r) {
  switch (r.quadrant & 3) {
    case 0:
      return kernel_sin(r.hi, r.lo);
    case 1:
      return kernel_cos(r.hi, r.lo);
    case 2:
      return -kernel_sin(r.hi, r.lo);
    default:
      return -kernel_cos(r.hi, r.lo);
  }
}

inline double cos_of(const Reduced& r) {
  switch (r.quadrant & 3) {
    case 0:
      return kernel_cos(r.hi, r.lo);
    case 1:
      return -kernel_sin(r.hi, r.lo);
    case 2:
      return -kernel_cos(r.hi, r.lo);
    default:
      return kernel_sin(r.hi, r.lo);
  }
}

// Single precision: a float result needs the double value to about 2^−33, so the series are shorter and the
// reduction takes two parts of π/2. Below this bound k·part stays exact and r holds about 60 bits.
constexpr double kFloatFastLimit = 0x1p19;

struct FloatReduced {
  double r;  // |r| ≤ π/4 + a little
  uint64_t quadrant;
};

inline FloatReduced reduce_float(double x) {
  const double kd = (x * kTwoOverPi + kRoundShift) - kRoundShift;
  const double r = (x - kd * kPiOver2Part1) - kd * (kPiOver2Part2 + kPiOver2Part3);
  return {r, static_cast<uint64_t>(static_cast<int64_t>(kd))};
}

// sin x to x^13/13! and cos x to x^12/12! for |x| ≤ π/4: the first term left out is below 2^−40 of the result.
inline double float_kernel_sin(double x) {
  const double z = x * x;
  return x +
         x * z *
             (-1.0 / 6 + z * (1.0 / 120 +
                              z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 + z * (1.0 / 6227020800))))));
}
inline double float_kernel_cos(double x) {
  const double z = x * x;
  return 1.0 + z * (-0.5 + z * (1.0 / 24 +
                                z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600))))));
}

// The quadrant's function of r: sin, cos, −sin or −cos.
inline float float_of_quadrant(double r, uint64_t quadrant) {
  const double v = (quadrant & 1) == 0 ? float_kernel_sin(r) : float_kernel_cos(r);
  return static_cast<float>((quadrant & 2) == 0 ? v : -v);
}

inline bool finite(double x) { return (std::bit_cast<uint64_t>(x) & 0x7ff0000000000000ull) != 0x7ff0000000000000ull; }

// The result for ±∞ and NaN: NaN given back as it came, and for ±∞ one fixed quiet NaN. (∞ − ∞ would give the
// processor's default NaN, negative on x86-64 and positive on arm64.)
inline double not_a_number(double x) { return x != x ? x : std::numeric_limits<double>::quiet_NaN(); }

}  // namespace

double sin(double x) {
  if (!finite(x)) return not_a_number(x);
  return sin_of(reduce(x));
}

double cos(double x) {
  if (!finite(x)) return not_a_number(x);
  return cos_of(reduce(x));
}

SinCos sincos(double x) {
  if (!finite(x)) return {not_a_number(x), not_a_number(x)};
  const Reduced r = reduce(x);
  return {sin_of(r), cos_of(r)};
}

float sin(float x) {
  if (x == 0.0f) return x;  // ±0 kept (the series would add a +0 to −0)
  const double d = x;
  if (d > -0x1.921fb54442d18p-1 && d < 0x1.921fb54442d18p-1) return static_cast<float>(float_kernel_sin(d));
  if (!(d > -kFloatFastLimit && d < kFloatFastLimit)) return static_cast<float>(sin(d));  // large, ±∞, NaN
  const FloatReduced r = reduce_float(d);
  return float_of_quadrant(r.r, r.quadrant);
}

SinCosF sincos(float x) {
  const double d = x;
  if (d > -0x1.921fb54442d18p-1 && d < 0x1.921fb54442d18p-1)
    return {x == 0.0f ? x : static_cast<float>(float_kernel_sin(d)), static_cast<float>(float_kernel_cos(d))};
  if (!(d > -kFloatFastLimit && d < kFloatFastLimit)) {
    const SinCos both = sincos(d);
    return {static_cast<float>(both.sin), static_cast<float>(both.cos)};
  }
  const FloatReduced r = reduce_float(d);
  return {float_of_quadrant(r.r, r.quadrant), float_of_quadrant(r.r, r.quadrant + 1)};
}

float cos(float x) {
  const double d = x;
  if (d > -0x1.921fb54442d18p-1 && d < 0x1.921fb54442d18p-1) return static_cast<float>(float_kernel_cos(d));
  if (!(d > -kFloatFastLimit && d < kFloatFastLimit)) return static_cast<float>(cos(d));
  const FloatReduced r = reduce_float(d);
  return float_of_quadrant(r.r, r.quadrant + 1);  // cos x = sin(x + π/2)
}

}  // namespace poet::math
