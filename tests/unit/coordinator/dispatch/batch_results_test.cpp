// Tests coordinator/dispatch/batch_results.cpp: results in, who gave them, what is final, and what is withdrawn
// from a worker found wrong.
#include "coordinator/dispatch/batch_results.h"

#include <gtest/gtest.h>

#include <vector>

namespace poet {
namespace {

std::vector<RolloutResult> scores(std::initializer_list<double> values) {
  std::vector<RolloutResult> out;
  for (double v : values) {
    RolloutResult r;
    r.total_reward = v;
    r.steps = 10;
    out.push_back(r);
  }
  return out;
}

using Ranges = std::vector<BatchResults::Range>;

// The ranges of what take_ready reports, each checked to hold its tasks' results (reward = task + 1, scores()).
Ranges ranges(const std::vector<BatchResults::Ready>& ready) {
  Ranges out;
  for (const BatchResults::Ready& r : ready) {
    for (size_t i = 0; i < r.results.size(); ++i) EXPECT_EQ(r.results[i].total_reward, double(r.first + i + 1));
    out.emplace_back(r.first, r.first + r.results.size());
  }
  return out;
}

TEST(BatchResults, FinalResultsAreReportedOnceAndHeldBackOnesWhenTheBatchIsWhole) {
  BatchResults book;
  book.start(6);
  EXPECT_EQ(book.remaining(), 6u);
  book.put(0, scores({1, 2}), "a", /*final_now=*/true);
  book.put(2, scores({3, 4}), "b", /*final_now=*/false);  // b may still be found wrong
  EXPECT_EQ(ranges(book.take_ready(false)), (Ranges{{0, 2}}));
  EXPECT_TRUE(book.take_ready(false).empty());  // once
  book.put(4, scores({5, 6}), "a", true);
  EXPECT_EQ(book.remaining(), 0u);
  EXPECT_EQ(ranges(book.take_ready(true)), (Ranges{{4, 6}, {2, 4}}));  // b's, now that the batch is whole
  EXPECT_EQ(book.results(2, 4)[1].total_reward, 4);
  const std::vector<RolloutResult> all = book.take();
  ASSERT_EQ(all.size(), 6u);
  EXPECT_EQ(all[5].total_reward, 6);
  EXPECT_EQ(book.remaining(), 0u);
}

TEST(BatchResults, AWrongWorkersResultsNotYetFinalAreWithdrawnInRanges) {
  BatchResults book;
  book.start(8);
  book.put(0, scores({1, 2}), "liar", false);
  book.put(2, scores({3}), "honest", false);
  book.put(3, scores({4, 5}), "liar", false);
  book.put(5, scores({6}), "liar", true);  // checked by another: final, it stands
  EXPECT_EQ(book.remaining(), 2u);
  EXPECT_EQ(book.withdraw("liar"), (Ranges{{0, 2}, {3, 5}}));
  EXPECT_EQ(book.remaining(), 6u);
  EXPECT_FALSE(book.has(0));
  EXPECT_TRUE(book.has(2));
  EXPECT_TRUE(book.has(5));
  EXPECT_TRUE(book.withdraw("liar").empty());
}

}  // namespace
}  // namespace poet
