// Tests simulation/es/centered_ranks.cpp: rank/(n − 1) − 0.5 with ascending ranks and ties broken by index.

#include "simulation/es/centered_ranks.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace poet {
namespace {

TEST(CenteredRanksTest, EmptyAndSingle) {
  EXPECT_TRUE(centered_ranks(std::vector<double>{}).empty());
  EXPECT_EQ(centered_ranks(std::vector<double>{42.0}), std::vector<double>{0.0});
}

TEST(CenteredRanksTest, TwoValues) {
  EXPECT_EQ(centered_ranks(std::vector<double>{3.0, -1.0}), (std::vector<double>{0.5, -0.5}));
  EXPECT_EQ(centered_ranks(std::vector<double>{-1.0, 3.0}), (std::vector<double>{-0.5, 0.5}));
}

// Returns 10, −5, 7, 0, 100 have ranks 3, 0, 2, 1, 4; n − 1 = 4.
TEST(CenteredRanksTest, DistinctValues) {
  const std::vector<double> r = centered_ranks(std::vector<double>{10.0, -5.0, 7.0, 0.0, 100.0});
  const std::vector<double> expected = {3.0 / 4 - 0.5, 0.0 / 4 - 0.5, 2.0 / 4 - 0.5, 1.0 / 4 - 0.5, 4.0 / 4 - 0.5};
  EXPECT_EQ(r, expected);
}

// Returns 1, 2, 1, 0, 2, 1: 0 → rank 0; the three 1s (indices 0, 2, 5) → 1, 2, 3; the two 2s (1, 4) → 4, 5.
TEST(CenteredRanksTest, TiesAreRankedByIndex) {
  const std::vector<double> r = centered_ranks(std::vector<double>{1.0, 2.0, 1.0, 0.0, 2.0, 1.0});
  const std::vector<double> ranks = {1, 4, 2, 0, 5, 3};
  ASSERT_EQ(r.size(), ranks.size());
  for (size_t i = 0; i < r.size(); ++i) EXPECT_EQ(r[i], ranks[i] / 5.0 - 0.5) << i;
}

TEST(CenteredRanksTest, AllEqualIsIndexOrder) {
  const std::vector<double> r = centered_ranks(std::vector<double>(4, 7.0));
  EXPECT_EQ(r, (std::vector<double>{-0.5, 1.0 / 3 - 0.5, 2.0 / 3 - 0.5, 0.5}));
}

TEST(CenteredRanksTest, InfiniteValuesRankAtTheEnds) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(centered_ranks(std::vector<double>{inf, 0.0, -inf}), (std::vector<double>{0.5, 0.0, -0.5}));
}

}  // namespace
}  // namespace poet
