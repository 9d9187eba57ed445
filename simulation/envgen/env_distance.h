#pragma once
// How far apart two environments are and how hard one is (spec §1.4, paper §4.3 Table 1): the 5-vector of an
// encoding, plain and normalised Euclidean distances on it, novelty against an archive, and difficulty levels.
// Stairs do not enter any of these (as in the reference and the paper).

#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "simulation/envgen/env_encoding.h"

namespace poet {

// e(A) = (roughness, gap lo, gap hi, stump height lo, stump height hi); an absent type counts as [0, 0].
using EnvVector = std::array<double, 5>;
inline constexpr EnvVector kEnvVectorMax = {8.0, 8.0, 8.0, 3.0, 3.0};  // e(Max), the normalisation

EnvVector env_vector(const EnvEncoding& encoding);

// ‖e(A) − e(B)‖₂, the reference's (unnormalised) novelty distance.
double euclidean_distance(const EnvEncoding& a, const EnvEncoding& b);

// ‖(e(A) − e(B)) / e(Max)‖₂ / √5: 1 between flat and (8, [8, 8], [3, 3]).
double normalized_distance(const EnvEncoding& a, const EnvEncoding& b);

// The mean of the k smallest distances (of all when there are fewer than k; 0 for none), summed in ascending order so
// that the order they come in does not matter: the novelty of a candidate from its distances to an archive, for any
// measure of distance. Throws std::invalid_argument when k < 1.
double mean_of_nearest(std::vector<double> distances, int k);

// The mean distance from candidate to its k nearest archive entries (plain Euclidean, or normalized_distance
// when asked); the mean over all of them when the archive has fewer than k, and 0 for an empty archive (nothing
// to be novel against). The archive's order does not matter. Throws std::invalid_argument when k < 1.
double novelty(const EnvEncoding& candidate, std::span<const EnvEncoding> archive, int k = 5, bool normalized = false);

// The number of Table 1 conditions met: stump height hi ≥ 2.4, gap hi ≥ 6.0, roughness ≥ 4.5.
enum class Difficulty { kEasy = 0, kChallenging, kVeryChallenging, kExtremelyChallenging };

inline constexpr double kChallengingStumpHeight = 2.4;
inline constexpr double kChallengingGap = 6.0;
inline constexpr double kChallengingRoughness = 4.5;

Difficulty difficulty(const EnvEncoding& encoding);
Difficulty difficulty(const EnvVector& e);  // the same conditions on a 5-vector (an absent type is [0, 0])

// Table 1's three measures of a 5-vector: roughness, the top of the gap range, the top of the stump range.
using ObstacleMeasures = std::array<double, 3>;
inline constexpr std::array<const char*, 3> kObstacleMeasureNames = {"roughness", "gap_hi", "stump_hi"};  // as keys
ObstacleMeasures obstacle_measures(const EnvVector& e);
// The obstacle frontier of a set of environments: each measure's largest value among them. Raises frontier to e's.
void raise_frontier(ObstacleMeasures& frontier, const EnvVector& e);

// normalized_distance on 5-vectors.
double normalized_distance(const EnvVector& a, const EnvVector& b);

// "easy", "challenging", "very challenging", "extremely challenging".
std::string_view to_string(Difficulty difficulty);

// An environment's level for people: to_string(difficulty(encoding)) for an obstacle course, "CPPN terrain" for a
// CPPN course, which Table 1's conditions do not describe (its 5-vector is all zeros).
std::string_view level_label(const EnvEncoding& encoding);

}  // namespace poet
