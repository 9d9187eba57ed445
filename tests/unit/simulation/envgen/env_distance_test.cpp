#include "simulation/envgen/env_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "simulation/envgen/mutation.h"

namespace poet {
namespace {

EnvEncoding rough(double r) {
  EnvEncoding e;
  e.roughness = r;
  return e;
}

EnvEncoding with_gap(EnvEncoding e, double lo, double hi) {
  e.pit_gap = Interval{lo, hi};
  return e;
}

EnvEncoding with_stumps(EnvEncoding e, double lo, double hi) {
  e.stump_width = Interval{1.0, 2.0};
  e.stump_height = Interval{lo, hi};
  e.stump_float = Interval{0.0, 1.0};
  return e;
}

EnvEncoding with_stairs(EnvEncoding e) {
  e.stair_height = Interval{1.0, 2.0};
  e.stair_width = Interval{4.0, 5.0};
  e.stair_steps = Interval{3.0, 5.0};
  return e;
}

const EnvEncoding kMax = with_stumps(with_gap(rough(8.0), 8.0, 8.0), 3.0, 3.0);

TEST(EnvDistanceVector, AbsentTypesAreZero) {
  EXPECT_EQ(env_vector(EnvEncoding{}), (EnvVector{0, 0, 0, 0, 0}));
  EXPECT_EQ(env_vector(with_stumps(with_gap(rough(1.5), 0.4, 1.2), 0.2, 0.6)), (EnvVector{1.5, 0.4, 1.2, 0.2, 0.6}));
  EXPECT_EQ(env_vector(with_stairs(rough(2.0))), (EnvVector{2.0, 0, 0, 0, 0}));
}

TEST(EnvDistance, FlatToTheMaximumIsOneNormalised) {
  EXPECT_DOUBLE_EQ(normalized_distance(EnvEncoding{}, kMax), 1.0);
  EXPECT_DOUBLE_EQ(normalized_distance(kMax, EnvEncoding{}), 1.0);
  EXPECT_DOUBLE_EQ(euclidean_distance(EnvEncoding{}, kMax), std::sqrt(3 * 64.0 + 2 * 9.0));
}

TEST(EnvDistance, RoughnessOnly) {
  EXPECT_DOUBLE_EQ(euclidean_distance(EnvEncoding{}, rough(3.0)), 3.0);
  EXPECT_DOUBLE_EQ(normalized_distance(EnvEncoding{}, rough(3.0)), (3.0 / 8.0) / std::sqrt(5.0));
}

TEST(EnvDistance, GapsAgainstStumps) {
  // e(A) = (1, 1, 3, 0, 0), e(B) = (0, 0, 0, 0.5, 2): differences 1, 1, 3, -0.5, -2
  const EnvEncoding a = with_gap(rough(1.0), 1.0, 3.0);
  const EnvEncoding b = with_stumps(EnvEncoding{}, 0.5, 2.0);
  EXPECT_DOUBLE_EQ(euclidean_distance(a, b), std::sqrt(1 + 1 + 9 + 0.25 + 4));
  EXPECT_DOUBLE_EQ(normalized_distance(a, b), std::sqrt(((1 + 1 + 9) / 64.0 + (0.25 + 4) / 9.0) / 5.0));
  EXPECT_DOUBLE_EQ(euclidean_distance(b, a), euclidean_distance(a, b));
}

TEST(EnvDistance, StairsAndNamesDoNotCount) {
  EnvEncoding a = with_stairs(rough(2.0));
  a.name = "a";
  EXPECT_EQ(euclidean_distance(a, rough(2.0)), 0.0);
  EXPECT_EQ(normalized_distance(a, rough(2.0)), 0.0);
}

TEST(EnvNovelty, MeanOfTheKNearest) {
  const std::vector<EnvEncoding> archive = {rough(10), rough(3), rough(0), rough(4), rough(1), rough(2)};
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive), (0 + 1 + 2 + 3 + 4) / 5.0);  // k = 5 by default
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 3), 1.0);
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 1), 0.0);
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 6), 20.0 / 6.0);
  EXPECT_DOUBLE_EQ(novelty(rough(9.0), archive, 2), (1 + 5) / 2.0);  // 10 and 4
}

TEST(EnvNovelty, FewerThanKIsTheMeanOverAll) {
  const std::vector<EnvEncoding> archive = {rough(1), rough(3)};
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive), 2.0);
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 100), 2.0);
}

TEST(EnvNovelty, EmptyArchiveIsZero) { EXPECT_EQ(novelty(rough(5.0), std::span<const EnvEncoding>{}), 0.0); }

TEST(EnvNovelty, TiedDistancesCountEachEntry) {
  const std::vector<EnvEncoding> archive = {rough(5), rough(1), rough(1)};
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 2), 1.0);
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 3), 7.0 / 3.0);
  // equal distances on either side of the candidate: either one may be chosen, the mean is the same
  EXPECT_DOUBLE_EQ(novelty(rough(2.0), std::vector<EnvEncoding>{rough(1), rough(3), rough(6)}, 1), 1.0);
}

TEST(EnvNovelty, ArchiveOrderDoesNotMatter) {
  std::vector<EnvEncoding> archive = {rough(0.3), with_gap(rough(1.1), 0.4, 1.2),
                                      rough(2.7), with_stumps(rough(0.1), 0.2, 0.6),
                                      rough(0.9), with_gap(with_stumps(rough(0.2), 0, 0.4), 0, 0.8),
                                      rough(4.4)};
  const EnvEncoding candidate = with_gap(rough(1.3), 0.4, 0.8);
  const double forward = novelty(candidate, archive);
  std::reverse(archive.begin(), archive.end());
  EXPECT_EQ(novelty(candidate, archive), forward);  // bit for bit
}

TEST(EnvNovelty, NormalisedOnRequest) {
  const std::vector<EnvEncoding> archive = {kMax};
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 5, true), 1.0);
  EXPECT_DOUBLE_EQ(novelty(EnvEncoding{}, archive, 5, false), std::sqrt(210.0));
}

TEST(EnvNovelty, RejectsKBelowOne) {
  const std::vector<EnvEncoding> archive = {rough(1)};
  EXPECT_THROW(novelty(EnvEncoding{}, archive, 0), std::invalid_argument);
}

TEST(EnvDifficulty, Levels) {
  EXPECT_EQ(difficulty(EnvEncoding{}), Difficulty::kEasy);
  // Gym's BipedalWalkerHardcore: stumps up to 2, gaps up to 3, roughness 1 meets none of the conditions
  EXPECT_EQ(difficulty(with_stumps(with_gap(rough(1.0), 0, 3.0), 0, 2.0)), Difficulty::kEasy);
  EXPECT_EQ(difficulty(with_stumps(EnvEncoding{}, 0, 2.2)), Difficulty::kEasy);
  EXPECT_EQ(difficulty(with_stumps(EnvEncoding{}, 0, 2.4)), Difficulty::kChallenging);
  EXPECT_EQ(difficulty(with_gap(EnvEncoding{}, 0, 5.6)), Difficulty::kEasy);
  EXPECT_EQ(difficulty(with_gap(EnvEncoding{}, 0, 6.0)), Difficulty::kChallenging);
  EXPECT_EQ(difficulty(rough(4.4)), Difficulty::kEasy);
  EXPECT_EQ(difficulty(rough(4.5)), Difficulty::kChallenging);
  EXPECT_EQ(difficulty(with_gap(with_stumps(EnvEncoding{}, 2.0, 2.4), 0, 6.0)), Difficulty::kVeryChallenging);
  EXPECT_EQ(difficulty(with_gap(rough(4.5), 0, 6.4)), Difficulty::kVeryChallenging);
  EXPECT_EQ(difficulty(with_gap(with_stumps(rough(4.5), 0, 2.4), 0, 6.0)), Difficulty::kExtremelyChallenging);
  EXPECT_EQ(difficulty(kMax), Difficulty::kExtremelyChallenging);
  EXPECT_EQ(difficulty(with_stairs(rough(1.0))), Difficulty::kEasy);  // stairs do not count
}

TEST(EnvDifficulty, ThresholdsAreReachedByMutationSteps) {
  // mutation rounds to the 0.1 grid, so 2.2 + 0.2 lands exactly on the 2.4 threshold
  EXPECT_EQ(difficulty(with_stumps(EnvEncoding{}, 0, round1(2.2 + 0.2))), Difficulty::kChallenging);
  EXPECT_EQ(difficulty(with_gap(EnvEncoding{}, 0, round1(5.6 + 0.4))), Difficulty::kChallenging);
}

TEST(EnvDifficulty, Names) {
  EXPECT_EQ(to_string(Difficulty::kEasy), "easy");
  EXPECT_EQ(to_string(Difficulty::kChallenging), "challenging");
  EXPECT_EQ(to_string(Difficulty::kVeryChallenging), "very challenging");
  EXPECT_EQ(to_string(Difficulty::kExtremelyChallenging), "extremely challenging");
}

}  // namespace
}  // namespace poet
