#pragma once
// Mutation of an environment encoding into a child (spec §1.3), with the reference's exact semantics: every
// random number comes from the caller's RandomStream, so a child is a pure function of (parent, options, stream).

#include <vector>

#include "schema_defaults.h"
#include "simulation/envgen/env_encoding.h"
#include "simulation/rng.h"

namespace poet {

// Which genes a run may change. The defaults are the schema's (MutationConfig): the paper's multi-obstacle runs
// (roughness, pits, stumps).
struct MutationOptions {
  bool roughness = schema_defaults::mutation_config::roughness;
  bool pits = schema_defaults::mutation_config::pits;
  bool stumps = schema_defaults::mutation_config::stumps;
  bool stairs = schema_defaults::mutation_config::stairs;
  // The reference sets the stair step count when stairs first appear and never changes it; the paper lists it
  // as mutable. Off = reference behaviour.
  bool mutate_stair_steps = schema_defaults::mutation_config::mutate_stair_steps;
  // The paper mutates "some or all" types. true (reference): every enabled type in every child. false: each
  // enabled type, in order, is mutated only if a uniform01() draw taken just before it is < 0.5; so a child
  // may come out equal to its parent (the POET loop drops duplicates).
  bool all_types = schema_defaults::mutation_config::all_types;
};

// How one interval gene moves: start value I, step s, maximum M, and the least hi − lo (0 for real genes,
// 1 for step counts, whose integer interval [lo, hi) must hold a value).
struct IntervalRule {
  Interval initial;
  double step = 0;
  double max = 0;
  double min_width = 0;
};

inline constexpr IntervalRule kPitGapRule{{0.0, 0.8}, 0.4, 8.0, 0.0};
inline constexpr IntervalRule kStumpHeightRule{{0.0, 0.4}, 0.2, 5.0, 0.0};
inline constexpr IntervalRule kStairHeightRule{{0.0, 0.4}, 0.2, 5.0, 0.0};
inline constexpr IntervalRule kStairStepsRule{{1.0, 2.0}, 1.0, 9.0, 1.0};
inline constexpr double kMaxMutatedRoughness = 10.0;
inline constexpr double kRoughnessStep = 0.6;  // r + U(−0.6, 0.6)

// The genes that are fixed whenever their type is present (spec §1.1).
inline constexpr Interval kStumpWidthOnAppear{1.0, 2.0};  // kept as the parent's once present
inline constexpr Interval kStumpFloat{0.0, 1.0};
inline constexpr Interval kStairWidth{4.0, 5.0};

// numpy's round(x, 1): rint(x·10)/10, ties to even on the scaled value (round1(0.65) = 0.6, as numpy gives).
double round1(double x);

// The roughness after adding the draw u: round1(r + u) clamped to [0, 10]; never −0.0.
double mutated_roughness(double r, double u);

// The legal moves of a present gene, in the reference's order: lo change (+s, 0, −s) outer, hi change
// (+s, 0, −s) inner, (0, 0) skipped, values rounded by round1. Empty when none is legal.
std::vector<Interval> legal_moves(const Interval& gene, const IntervalRule& rule);

// An absent gene becomes rule.initial with no draw; a present one moves to legal_moves()[uniform_int(0, n)]
// (no draw when n ≤ 1, as numpy's randint), or stays unchanged when n = 0.
Interval mutate_interval(const std::optional<Interval>& gene, const IntervalRule& rule, RandomStream& stream);

// The child's genes, mutated in the order roughness, pits, stumps, stairs; types disabled in options are copied
// unchanged. The child's name is reference_name(child). Precondition: validate(parent) passes; then so does
// validate(child).
EnvEncoding mutate(const EnvEncoding& parent, const MutationOptions& options, RandomStream& stream);

// mutate() of the encoding (mutate_cppn() of a CPPN course's genome, which the options do not concern), then the
// child's terrain seed: uniform_int(0, kMaxEnvSeed) from the same stream.
EnvDef mutate_def(const EnvDef& parent, const MutationOptions& options, RandomStream& stream);

}  // namespace poet
