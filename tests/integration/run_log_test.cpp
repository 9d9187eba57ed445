// The coordinator's log at its default level: the events that change the population and one line per
// reproduction, not every mutation attempt; --verbose adds those.

#include <gtest/gtest.h>

#include <string>

#include "coordinator_run_fixture.h"

namespace {

using namespace poet::testing;
using RunLogTest = CoordinatorRunTest;

TEST_F(RunLogTest, MutationAttemptsAreLoggedOnlyWhenVerbose) {
  const pid_t quiet = coordinator(root_ / "Q", {"--threads", "2"}, "Q");
  ASSERT_EQ(wait(quiet), 0) << read(root_ / "Q.err");
  const std::string log = read(root_ / "Q.err");
  EXPECT_TRUE(contains(log, ": reproduction eligible=")) << log;
  EXPECT_TRUE(contains(log, ": pair_created ")) << log;
  EXPECT_FALSE(contains(log, ": child attempt=")) << log;
  EXPECT_TRUE(contains(read(root_ / "Q" / "events.jsonl"), "\"event\":\"child\"")) << "the events keep them";

  const pid_t verbose = coordinator(root_ / "V", {"--threads", "2", "--verbose"}, "V");
  ASSERT_EQ(wait(verbose), 0) << read(root_ / "V.err");
  EXPECT_TRUE(contains(read(root_ / "V.err"), ": child attempt=")) << read(root_ / "V.err");
  expect_same_run(root_ / "Q", root_ / "V");
}

}  // namespace
