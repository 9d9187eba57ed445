// Tests common/formats/course_sweep_json.cpp: a sweep's JSON carries its counts and names the seeds it finished on.

#include "common/formats/course_sweep_json.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

RolloutResult episode(double total_reward, int steps, bool finished, bool fell) {
  RolloutResult r;
  r.total_reward = total_reward;
  r.steps = steps;
  r.finished = finished;
  r.fell = fell;
  return r;
}

TEST(CourseSweepJson, CarriesTheCountsAndNamesTheSeedsItFinishedOn) {
  const CourseSweep sweep{
      "flat", 3, {episode(300.5, 900, true, false), episode(-100, 40, false, true), episode(250, 1000, true, false)}};
  const nlohmann::json j = to_json(sweep);
  EXPECT_EQ(j["course"], "flat");
  EXPECT_EQ(j["first_seed"], 3);
  EXPECT_EQ(j["episodes"], 3);
  EXPECT_EQ(j["finished"], 2);
  EXPECT_EQ(j["fell"], 1);
  EXPECT_EQ(j["timed_out"], 0);
  EXPECT_EQ(j["returns"], nlohmann::json::array({300.5, -100.0, 250.0}));
  EXPECT_EQ(j["steps"], nlohmann::json::array({900, 40, 1000}));
  EXPECT_EQ(j["finished_seeds"], nlohmann::json::array({3, 5}));
  EXPECT_DOUBLE_EQ(j["max_return"].get<double>(), 300.5);

  EXPECT_TRUE(to_json(CourseSweep{"flat", 0, {episode(1, 50, false, false)}})["finished_seeds"].empty());
}

}  // namespace
}  // namespace poet
