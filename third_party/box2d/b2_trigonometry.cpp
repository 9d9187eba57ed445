// b2SinCos, which project-trigonometry.patch declares in Box2D's b2_math.h for b2Rot: the project's sine and
// cosine (math/), so that a rotation has the same bits on every processor and C library, not glibc's sinf and cosf,
// whose results depend on the processor. One reduction gives both.

#include "box2d/b2_math.h"
#include "math/trigonometry.h"

void b2SinCos(float angle, float* s, float* c) {
  const poet::math::SinCosF both = poet::math::sincos(angle);
  *s = both.sin;
  *c = both.cos;
}
