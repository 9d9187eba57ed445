// The C library's exp, log, pow, sin and cos behind the project's math API (math/*.h), for comparisons only:
// as an object on a program's link line it defines every function before the linker reaches poet_math's archive,
// whose members are then never pulled in. Linked into walker_bench_libm (bench/math_cost.sh sets it beside
// walker_bench) and the tests' poet-libm-fingerprint (the probe seeing the C library's bits change under a
// processor mask), never into the project's programs: these are the functions whose last bits vary between machines.

#include <cmath>

#include "math/exponential.h"
#include "math/trigonometry.h"

namespace poet::math {

double exp(double x) { return std::exp(x); }
double log(double x) { return std::log(x); }
double power(double base, uint64_t n) { return std::pow(base, static_cast<double>(n)); }
double sin(double x) { return std::sin(x); }
double cos(double x) { return std::cos(x); }
SinCos sincos(double x) { return {std::sin(x), std::cos(x)}; }
float sin(float x) { return sinf(x); }
float cos(float x) { return cosf(x); }
SinCosF sincos(float x) { return {sinf(x), cosf(x)}; }

}  // namespace poet::math
