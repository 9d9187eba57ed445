#include "coordinator/dispatch/running_median.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "simulation/rng.h"

namespace poet {
namespace {

TEST(RunningMedian, IsTheValueAtHalfTheCountOfTheSortedValuesAfterEveryAddition) {
  RandomStream draw(stream_key(5, "running-median-test"));
  for (const int64_t range : {int64_t{3}, int64_t{1000}}) {  // with many ties, and with few
    RunningMedian median;
    std::vector<int64_t> seen;
    EXPECT_TRUE(median.empty());
    for (int i = 0; i < 500; ++i) {
      const int64_t value = draw.uniform_int(0, range);
      median.add(value);
      seen.push_back(value);
      std::vector<int64_t> sorted = seen;
      std::sort(sorted.begin(), sorted.end());
      ASSERT_EQ(median.median(), sorted[sorted.size() / 2]) << "after " << seen.size() << " values";
    }
    median.clear();
    EXPECT_TRUE(median.empty());
  }
}

}  // namespace
}  // namespace poet
