#include "common/program/build_fingerprint.h"

#include <box2d/b2_common.h>

#include <bit>
#include <cfloat>
#include <initializer_list>

#include "common/program/command_line.h"
#include "common/text/text_format.h"
#include "simulation/arithmetic_probe.h"
#include "simulation/rng.h"
#include "simulation/walker/walker_constants.h"

// Each guard refuses a build whose arithmetic could differ from the coordinator's or a worker's.
#ifdef __FAST_MATH__
#error "-ffast-math reorders and reassociates floating-point operations: results would depend on the compiler"
#endif
#ifdef __FMA__
#error "FMA enabled: a*b+c rounded once gives different numbers from machines without FMA (see cmake/FloatMode.cmake)"
#endif
#if (defined(__x86_64__) || defined(__i386__)) && FLT_EVAL_METHOD != 0
#error "FLT_EVAL_METHOD != 0: x87 excess precision makes results depend on register spills (use -mfpmath=sse)"
#endif
#ifndef POET_FLOAT_MODE
#error "POET_FLOAT_MODE is defined by cmake/FloatMode.cmake"
#endif

namespace poet {
namespace {

// Folds values into a 64-bit digest by their bit patterns (doubles exactly, -0.0 and 0.0 apart).
class Digest {
 public:
  constexpr void add(double x) { add(std::bit_cast<uint64_t>(x)); }
  constexpr void add(std::initializer_list<double> xs) {
    for (double x : xs) add(x);
  }
  constexpr void add(int x) { add(static_cast<uint64_t>(static_cast<int64_t>(x))); }
  constexpr void add(unsigned x) { add(static_cast<uint64_t>(x)); }
  constexpr void add(uint64_t x) { h_ = mix64(h_ ^ (x + kGoldenGamma)); }
  constexpr uint64_t value() const { return h_; }

 private:
  uint64_t h_ = hash_name("poet walker constants");
};

// Every constant of walker/walker_constants.h: physics, bodies and joints, lidar, terrain, start, reward, limits.
constexpr uint64_t walker_constants_digest() {
  using namespace walker;
  Digest d;
  d.add({kScale, kFps, kGravity});
  d.add(kVelocityIterations);
  d.add(kPositionIterations);
  d.add({kMotorsTorque, kSpeedHip, kSpeedKnee, kLidarRange});
  d.add(kLidarRays);
  d.add(kDefaultPushScale);
  for (const auto& vertex : kHullPoly) d.add({vertex[0], vertex[1]});
  d.add({kHullDensity, kHullFriction, kLegDown, kLegW, kLegH, kLowerLegWidthFactor, kLegDensity, kLegFriction});
  d.add({kHipLower, kHipUpper, kKneeLower, kKneeUpper, kLegStartAngle});
  d.add(kGroundCategory);
  d.add(kWalkerCategory);
  d.add(kTerrainStep);
  d.add(kTerrainLength);
  d.add(kTerrainHeight);
  d.add(kTerrainGrass);
  d.add(kTerrainStartpad);
  d.add({kTerrainFriction, kPitDepthSteps, kMinObstacleHeightSteps, kInitX, kInitY, kFinishX});
  d.add({kTorqueCost, kFallReward});
  d.add(kDefaultTimeLimit);
  return d.value();
}

const char* compiler() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "g++ " __VERSION__;
#else
  return "unknown";
#endif
}

// The ISA the arithmetic runs on; the guards above make the x86-64 description true.
const char* target() {
#if defined(__x86_64__)
  return "x86-64 (SSE2 doubles, no FMA)";
#elif defined(__aarch64__)
  return "aarch64 (no FMA contraction)";
#else
  return "unknown processor (no FMA contraction)";
#endif
}

// The lines the digest covers: what decides the numbers, the same on every machine that computes them alike.
std::string compared_lines() {
  std::string text;
  text += "poet: " + std::string(project_version()) + "\n";
  text += std::string("compiler: ") + compiler() + "\n";
  // the library's own b2_version, then the source it was built from: Debian's 2.4.1 source reports 2.4.0
  text += "box2d: " + std::to_string(b2_version.major) + "." + std::to_string(b2_version.minor) + "." +
          std::to_string(b2_version.revision) + " (b2_version; built from Debian's source package " +
          POET_BOX2D_PACKAGE_VERSION ")\n";
  text += "walker: " + hex_text(walker_constants_digest()) + "\n";
  const ArithmeticProbe probe = probe_arithmetic();
  text += "arithmetic: " + hex_text(probe.digest()) + " (math " + hex_text(probe.math) + ", box2d " +
          hex_text(probe.box2d) + ", walker " + hex_text(probe.walker) + ")\n";
  return text;
}

}  // namespace

uint64_t build_fingerprint_digest() {
  static const uint64_t digest = mix64(hash_name(compared_lines()));
  return digest;
}

uint64_t arithmetic_digest() { return probe_arithmetic().digest(); }

std::string arithmetic_text() {
  const ArithmeticProbe probe = probe_arithmetic();
  return "math " + hex_text(probe.math) + ", box2d " + hex_text(probe.box2d) + ", walker " + hex_text(probe.walker);
}

std::string build_fingerprint() {
  // float mode and target are told, not compared: machines of other ISAs that compute alike share the digest
  return compared_lines() + "float mode: " POET_FLOAT_MODE "\n" + "target: " + target() + "\n" +
         "digest: " + hex_text(build_fingerprint_digest()) + "\n";
}

std::string build_fingerprint_line() {
  return "digest " + hex_text(build_fingerprint_digest()) + ", arithmetic " + hex_text(arithmetic_digest()) +
         ", float mode " POET_FLOAT_MODE;
}

}  // namespace poet
