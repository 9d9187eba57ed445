#pragma once
// The genome of an environment (spec §1.1): ground roughness and the obstacle intervals, plus the terrain seed
// that turns an encoding into one exact course (EnvDef). Units are terrain steps (14/30 m) for sizes.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "simulation/envgen/cppn_genome.h"

namespace poet {

// A closed interval [lo, hi] of a gene. Real-valued genes are sampled uniformly in [lo, hi); integer genes
// (stump width and float, stair width and step count) are sampled as integers in [lo, hi).
struct Interval {
  double lo = 0;
  double hi = 0;
  friend bool operator==(const Interval&, const Interval&) = default;
};

// An obstacle type is present when all of its intervals are; an absent type has all of them empty
// (the reference's empty lists). Encodings that give some but not all of a type's intervals are invalid.
// A CPPN course (Enhanced POET) is the second kind: its ground is drawn by the genome (envgen/cppn_course.h), with
// roughness 0 and no obstacle type.
struct EnvEncoding {
  std::string name = "flat";  // a label carried in files; never part of an environment's identity
  double roughness = 0;
  std::optional<Interval> pit_gap;
  std::optional<Interval> stump_width;
  std::optional<Interval> stump_height;
  std::optional<Interval> stump_float;
  std::optional<Interval> stair_height;
  std::optional<Interval> stair_width;
  std::optional<Interval> stair_steps;
  std::shared_ptr<const CppnGenome> cppn;  // shared: an encoding is copied into every task on its course

  bool is_cppn() const { return cppn != nullptr; }
  bool has_pits() const { return pit_gap.has_value(); }
  bool has_stumps() const { return stump_width && stump_height && stump_float; }
  bool has_stairs() const { return stair_height && stair_width && stair_steps; }

  // Equal genes (every interval, the roughness and the genome); the name is ignored.
  bool same_genes(const EnvEncoding& other) const;
};

// One exact course: an encoding and the terrain seed in [0, 10^6) that the course is drawn with.
struct EnvDef {
  EnvEncoding encoding;
  uint32_t seed = 0;
};

inline constexpr uint32_t kMaxEnvSeed = 1'000'000;  // seeds are drawn in [0, kMaxEnvSeed)

// The largest sizes a course may ask for; beyond them a course stops being a walker course (and Box2D's
// float coordinates lose precision). Mutation's own maxima (spec §1.3) sit well inside.
inline constexpr double kMaxRoughness = 20.0;
inline constexpr double kMaxIntervalValue = 20.0;  // any interval bound, in terrain steps or counts

// Checks every field of an encoding: finite, non-negative, lo <= hi, integer genes whole with lo < hi, types
// complete, within the maxima; a CPPN course's genome as validate_cppn_course checks it. Returns a message naming the
// first bad field, or nothing when valid.
std::optional<std::string> validate(const EnvEncoding& encoding);

// The reference's label r<rough>[.p<lo>_<hi>][.b<w>_<hlo>_<hhi>][.s<steps_lo>_<stair_h_hi>], numbers in
// Python's float form ("0.0", "0.8", "1.0"); cppn_name() for a CPPN course. It omits the seed and some genes: a
// label, never an identity.
std::string reference_name(const EnvEncoding& encoding);

}  // namespace poet
