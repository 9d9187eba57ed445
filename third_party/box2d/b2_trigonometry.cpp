// b2Sin and b2Cos, which project-trigonometry.patch declares in Box2D's b2_math.h for b2Rot: the project's sine
// and cosine (math/), so that a rotation has the same bits on every processor and C library, not glibc's sinf and
// cosf, whose results depend on the processor.

#include "box2d/b2_math.h"
#include "math/trigonometry.h"

float b2Sin(float angle) { return poet::math::sin(angle); }

float b2Cos(float angle) { return poet::math::cos(angle); }
