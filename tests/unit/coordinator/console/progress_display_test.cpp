// The progress line's text, and that --quiet turns the display off.

#include "coordinator/console/progress_display.h"

#include <gtest/gtest.h>

#include "engine/engine.h"
#include "run_directory/config/run_config.h"

namespace poet {
namespace {

RunState two_pairs_one_retired() {
  pb::RunConfig config;
  config.set_iterations(200);
  RunState s = initial_state(run_settings(config));
  s.next_iteration = 42;
  s.pairs[0].latest_score = 12.34;
  s.pairs[0].first_solved_iteration = 30;
  Pair other = s.pairs[0];
  other.id = 1;
  other.latest_score = 250;  // retired: not among the active pairs' best
  other.retired_iteration = 40;
  other.first_solved_iteration = kNone;
  s.pairs.push_back(other);
  return s;
}

TEST(ProgressLine, ShowsIterationPairsBestSolvedRateAndEta) {
  const std::string line = progress_line(two_pairs_one_retired(), 1234.4, 125);
  EXPECT_NE(line.find("iteration 42/200"), std::string::npos) << line;
  EXPECT_NE(line.find("pairs 1"), std::string::npos) << line;
  EXPECT_NE(line.find("best 12.3"), std::string::npos) << line;
  EXPECT_NE(line.find("solved 1"), std::string::npos) << line;
  EXPECT_NE(line.find("1234 rollouts/s"), std::string::npos) << line;
  EXPECT_NE(line.find("ETA"), std::string::npos) << line;
}

TEST(ProgressLine, UnknownRatesAreLeftOut) {
  const std::string line = progress_line(two_pairs_one_retired(), -1, -1);
  EXPECT_EQ(line.find("rollouts/s"), std::string::npos) << line;
  EXPECT_EQ(line.find("ETA"), std::string::npos) << line;
}

TEST(ProgressDisplay, QuietMeansOff) {
  EXPECT_FALSE(ProgressDisplay(false).enabled());
  EXPECT_FALSE(ProgressDisplay(false, true).enabled());
  EXPECT_TRUE(ProgressDisplay(true, true).enabled());
}

}  // namespace
}  // namespace poet
