#pragma once
// What this machine computes, as digests: the project's math over fixed inputs, a few steps of a bare Box2D
// world, and an episode's start of the walker (course, policy, lidar, physics). Equal digests on two machines
// mean they computed these bit for bit alike; the build's fingerprint carries them, and the coordinator refuses
// a worker whose digests differ from its own before giving it any work.

#include <cstdint>

namespace poet {

struct ArithmeticProbe {
  uint64_t math = 0;        // exp, log, tanh, power, sin, cos and sincos (double and float) over fixed inputs
  uint64_t box2d = 0;       // a box falling onto ground and a motored revolute joint, 120 steps
  uint64_t walker = 0;      // the walker on a fixed course with a fixed policy, 150 steps: observations and rewards
  uint64_t digest() const;  // the three folded into one
};

// Runs the probe (a few milliseconds). The same values on every call in a process.
ArithmeticProbe probe_arithmetic();

}  // namespace poet
