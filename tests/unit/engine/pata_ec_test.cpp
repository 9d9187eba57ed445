// Tests engine/pata_ec.cpp on an example computed by hand: four agents' scores on three archived
// environments and one candidate, the minimal criterion [50, 300].

#include "engine/pata_ec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace poet {
namespace {

constexpr double kLow = 50, kHigh = 300;
constexpr double kSixth = 1.0 / 6;

void expect_near(const PataEc& got, const PataEc& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-12) << i;
}

// Four agents: ranks 0..3 become rank/3 − 0.5, i.e. −1/2, −1/6, 1/6, 1/2.
const PataEc kA = {-0.5, -kSixth, 0.5, kSixth};
const PataEc kB = {-0.5, -kSixth, kSixth, 0.5};
const PataEc kC = {0.5, kSixth, -0.5, -kSixth};
const PataEc kCandidate = {-kSixth, -0.5, kSixth, 0.5};

TEST(PataEc, ClipsThenRanks) {
  // A: (10, 120, 400, 200) → clipped (50, 120, 300, 200) → ranks (0, 1, 3, 2)
  expect_near(pata_ec(std::vector<double>{10, 120, 400, 200}, kLow, kHigh), kA);
  // B: (−20, 30, 250, 500) → (50, 50, 250, 300): the tie at 50 ranks in agent order → ranks (0, 1, 2, 3)
  expect_near(pata_ec(std::vector<double>{-20, 30, 250, 500}, kLow, kHigh), kB);
  // C: (310, 290, 5, 100) → (300, 290, 50, 100) → ranks (3, 2, 0, 1)
  expect_near(pata_ec(std::vector<double>{310, 290, 5, 100}, kLow, kHigh), kC);
  // candidate: (60, 40, 350, 300) → (60, 50, 300, 300): the tie at 300 in agent order → ranks (1, 0, 2, 3)
  expect_near(pata_ec(std::vector<double>{60, 40, 350, 300}, kLow, kHigh), kCandidate);
}

TEST(PataEc, EdgeCasesOfTheRanks) {
  expect_near(pata_ec(std::vector<double>{123}, kLow, kHigh), {0.0});  // one agent: the centre
  EXPECT_TRUE(pata_ec(std::vector<double>{}, kLow, kHigh).empty());
  // every agent fails alike: the same PATA-EC whatever the scores below the bound
  expect_near(pata_ec(std::vector<double>{-100, 0, 49}, kLow, kHigh), {-0.5, 0.0, 0.5});
  expect_near(pata_ec(std::vector<double>{-5, -80, 10}, kLow, kHigh), {-0.5, 0.0, 0.5});
}

TEST(PataEc, NoveltyIsTheMeanDistanceToTheKNearest) {
  // candidate − A = (1/3, −1/3, −1/3, 1/3): √(4/9) = 2/3
  // candidate − B = (1/3, −1/3, 0, 0):       √(2/9) = √2/3 ≈ 0.4714
  // candidate − C = (−2/3, −2/3, 2/3, 2/3):  √(16/9) = 4/3
  const std::vector<PataEc> archive = {kA, kB, kC};
  EXPECT_NEAR(pata_ec_novelty(kCandidate, archive, 1), std::sqrt(2.0) / 3, 1e-12);
  EXPECT_NEAR(pata_ec_novelty(kCandidate, archive, 2), (std::sqrt(2.0) / 3 + 2.0 / 3) / 2, 1e-12);  // ≈ 0.5690
  // fewer than k: the mean over all three, (√2/3 + 2/3 + 4/3)/3 ≈ 0.8238
  EXPECT_NEAR(pata_ec_novelty(kCandidate, archive, 5), (std::sqrt(2.0) / 3 + 2.0) / 3, 1e-12);
  // the archive's order does not matter
  const std::vector<PataEc> reversed = {kC, kB, kA};
  EXPECT_EQ(pata_ec_novelty(kCandidate, reversed, 2), pata_ec_novelty(kCandidate, archive, 2));
  // an environment characterised like an archived one is not novel
  EXPECT_EQ(pata_ec_novelty(kB, archive, 1), 0.0);
}

TEST(PataEc, NoveltyOfAnEmptyArchiveIsZeroAndBadArgumentsThrow) {
  EXPECT_EQ(pata_ec_novelty(kCandidate, {}, 5), 0.0);
  const std::vector<PataEc> archive = {kA};
  EXPECT_THROW(pata_ec_novelty(kCandidate, archive, 0), std::invalid_argument);
  const std::vector<PataEc> shorter = {{0.0}};
  EXPECT_THROW(pata_ec_novelty(kCandidate, shorter, 5), std::invalid_argument);
}

}  // namespace
}  // namespace poet
