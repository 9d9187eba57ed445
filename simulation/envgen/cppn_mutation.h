#pragma once
// Mutation of a CPPN terrain genome into a child (Enhanced POET, Wang et al. 2020, with neat-python's single
// structural mutation): every random number comes from the caller's RandomStream, so a child is a pure function
// of (parent, stream).

#include "simulation/envgen/cppn_genome.h"
#include "simulation/rng.h"

namespace poet {

inline constexpr double kCppnPerturbProbability = 0.75;  // each weight and bias, independently
inline constexpr double kCppnPerturbStddev = 0.1;        // N(0, 0.1²), then clamped to ±kCppnParamLimit
inline constexpr double kCppnAddNodeProbability = 0.1;   // at most one structural mutation a child
inline constexpr double kCppnDeleteNodeProbability = 0.075;
inline constexpr double kCppnSeedWeightStddev = 0.25;  // the first genome: input → output, weight N(0, 0.25²)
inline constexpr double kCppnBiasStddev = 0.1;         // its output's bias, and a new node's, N(0, 0.1²)
// The normalisation of a child's rise m (the highest point of the course above the start pad's end): a rise below
// 0.25 m is scaled to U(0.25, 0.75) m, one above 16 m to U(12, 16) m; a course with no rise is redrawn.
inline constexpr double kCppnMinRise = 0.25, kCppnLowRiseTo[2] = {0.25, 0.75};
inline constexpr double kCppnMaxRise = 16.0, kCppnHighRiseTo[2] = {12.0, 16.0};
inline constexpr int kCppnMaxDraws = 1000;

enum class CppnStructuralMutation { kNone, kAddNode, kDeleteNode };

// The draw that makes one candidate child, without checks: r = uniform01() picks add node (r < 0.1: a random
// connection is split — removed, and a hidden node with a random activation and bias N(0, 0.1²) takes
// from →(weight 1) new →(its weight) to), delete node (r < 0.175: a random hidden node and its connections go) or
// nothing (also when there is nothing to split or delete); then every connection's weight and every non-input
// node's bias, in canonical order, is perturbed with probability 0.75. Reports the structural mutation made.
CppnGenome draw_cppn_child(const CppnGenome& parent, RandomStream& stream, CppnStructuralMutation* made = nullptr);

// The rise normalisation above, applied to a drawn child in place. Returns false when the child must be redrawn:
// no rise, or a relief that overflows.
bool normalize_cppn_rise(CppnGenome& child, RandomStream& stream);

// A child: draws until one differs from its parent, has a path from input to output, has a rise to normalise, and
// makes a valid course (validate_cppn_course). The domain of the normalisation is the course's own x′ points,
// where the authors' mutation test samples x in [−1, 1) instead while their terrain reads [−π, π): one domain
// for both here, so the bounds hold on the course walked. Returns the parent unchanged when kCppnMaxDraws draws
// all fail (the POET loop then drops it as a duplicate).
CppnGenome mutate_cppn(const CppnGenome& parent, RandomStream& stream);

// The first genome of a run: cppn_seed_genome(N(0, 0.25²), N(0, 0.1²)), each clamped to ±kCppnParamLimit.
CppnGenome first_cppn_genome(RandomStream& stream);

}  // namespace poet
