// Tests simulation/suite/course_suite.cpp: a named suite is a fixed set of courses (pinned here, so a changed
// definition must take a new name), each group at its level; a suite's episodes do not depend on the thread count;
// the statistics are the textbook ones.

#include "simulation/suite/course_suite.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "common/formats/policy/policy_file.h"
#include "simulation/envgen/env_distance.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

// Every gene of every course and every seed, in order.
uint64_t suite_digest(const CourseSuite& suite) {
  uint64_t h = hash_name(suite.name);
  auto add = [&h](uint64_t x) { h = mix64(h ^ x); };
  auto add_interval = [&](const std::optional<Interval>& i) {
    add(i.has_value());
    if (i) add(std::bit_cast<uint64_t>(i->lo)), add(std::bit_cast<uint64_t>(i->hi));
  };
  for (const SuiteGroup& g : suite.groups) {
    add(hash_name(g.name));
    for (const SuiteCourse& c : g.courses) {
      add(hash_name(c.encoding.name));
      add(std::bit_cast<uint64_t>(c.encoding.roughness));
      for (const auto* i :
           {&c.encoding.pit_gap, &c.encoding.stump_width, &c.encoding.stump_height, &c.encoding.stump_float,
            &c.encoding.stair_height, &c.encoding.stair_width, &c.encoding.stair_steps})
        add_interval(*i);
      for (uint32_t seed : c.seeds) add(seed);
    }
  }
  return h;
}

TEST(CourseSuite, SuiteV1IsPinned) {
  const std::optional<CourseSuite> suite = named_suite("poet-suite-v1");
  ASSERT_TRUE(suite);
  // A failure here means poet-suite-v1's courses changed: give the changed suite a new name instead.
  EXPECT_EQ(suite_digest(*suite), 0xf1a9dac1a6ca5d04ULL);
  EXPECT_EQ(suite->episodes(), 500);
  ASSERT_EQ(suite->groups.size(), 5u);
  const char* names[] = {"easy", "challenging", "very challenging", "extremely challenging", "hardcore-like"};
  for (size_t g = 0; g < 5; ++g) {
    EXPECT_EQ(suite->groups[g].name, names[g]);
    EXPECT_EQ(suite->groups[g].episodes(), 100);
  }
  EXPECT_EQ(suite->groups[1].courses[7].encoding.name, "challenging-07");
  EXPECT_EQ(suite->groups[4].courses.size(), 1u);
  EXPECT_EQ(suite->groups[4].courses[0].encoding.name, "hardcore-like");
  EXPECT_TRUE(suite->groups[4].courses[0].encoding.has_stairs());
}

TEST(CourseSuite, EachLevelGroupHoldsValidCoursesOfItsLevelOnSeedsInRange) {
  const CourseSuite suite = named_suite("poet-suite-v1").value();
  for (int level = 0; level <= 3; ++level)
    for (const SuiteCourse& c : suite.groups[static_cast<size_t>(level)].courses) {
      EXPECT_EQ(validate(c.encoding), std::nullopt) << c.encoding.name;
      EXPECT_EQ(static_cast<int>(difficulty(c.encoding)), level) << c.encoding.name;
      EXPECT_FALSE(c.encoding.has_stairs());
      for (uint32_t seed : c.seeds) EXPECT_LT(seed, kMaxEnvSeed);
    }
}

TEST(CourseSuite, UnknownNamesAndEmptySuitesAreRefused) {
  EXPECT_FALSE(named_suite("poet-suite-v0"));
  EXPECT_FALSE(named_suite(""));
  ASSERT_FALSE(suite_names().empty());
  for (std::string_view name : suite_names()) EXPECT_TRUE(named_suite(name)) << name;
  EXPECT_THROW(make_suite("x", 1, 0, 1), std::invalid_argument);
  EXPECT_THROW(make_suite("x", 1, 1, 0), std::invalid_argument);
}

TEST(CourseSuite, EpisodesDoNotDependOnTheThreadCount) {
  const Expected<PolicyFile> walker = load_policy(std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json");
  ASSERT_TRUE(walker) << walker.error();
  const Mlp policy(walker->params);
  const CourseSuite suite = make_suite("small", 7, 2, 2);
  ASSERT_EQ(suite.episodes(), 20);
  const SuiteScore one = run_suite(policy, suite, {}, 300, 1);
  const SuiteScore three = run_suite(policy, suite, {}, 300, 3);
  ASSERT_EQ(one.groups.size(), 5u);
  ASSERT_EQ(three.groups.size(), 5u);
  for (size_t g = 0; g < 5; ++g) {
    ASSERT_EQ(one.groups[g].episodes.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(std::bit_cast<uint64_t>(one.groups[g].episodes[i].total_reward),
                std::bit_cast<uint64_t>(three.groups[g].episodes[i].total_reward));
      EXPECT_EQ(one.groups[g].episodes[i].steps, three.groups[g].episodes[i].steps);
    }
  }
  EXPECT_EQ(one.episodes(), 20);
}

RolloutResult episode(double reward, bool finished) {
  RolloutResult r;
  r.total_reward = reward;
  r.finished = finished;
  return r;
}

TEST(CourseSuite, StatisticsAreWilsonsIntervalAndTheMeansOwn) {
  GroupScore none{"g", std::vector<RolloutResult>(100, episode(-100, false))};
  EXPECT_EQ(none.finished(), 0);
  EXPECT_DOUBLE_EQ(none.finished_interval().first, 0.0);
  EXPECT_NEAR(none.finished_interval().second, 0.0370, 5e-4);  // 1.96² / (100 + 1.96²)
  GroupScore half{"g", {}};
  for (int i = 0; i < 100; ++i) half.episodes.push_back(episode(i % 2 ? 300 : 100, i % 2 == 1));
  EXPECT_DOUBLE_EQ(half.finished_fraction(), 0.5);
  EXPECT_NEAR(half.finished_interval().first, 0.4038, 5e-4);
  EXPECT_NEAR(half.finished_interval().second, 0.5962, 5e-4);
  EXPECT_DOUBLE_EQ(half.mean_return(), 200);
  EXPECT_NEAR(half.return_sd(), 100 * std::sqrt(100.0 / 99.0), 1e-9);
  EXPECT_NEAR(half.mean_return_half_width(), 1.959964 * half.return_sd() / 10, 1e-5);
  RolloutResult start, halfway, beyond;
  start.final_x = walker::kInitX - 1;  // walked backwards: no progress
  halfway.final_x = (walker::kInitX + walker::kFinishX) / 2;
  beyond.final_x = walker::kFinishX + 3;
  EXPECT_EQ(progress(start), 0);
  EXPECT_DOUBLE_EQ(progress(halfway), 0.5);
  EXPECT_EQ(progress(beyond), 1);
  EXPECT_DOUBLE_EQ((GroupScore{"g", {start, halfway, beyond}}.mean_progress()), 0.5);
  const SuiteScore both{"s", {none, half}};
  EXPECT_EQ(both.episodes(), 200);
  EXPECT_EQ(both.finished(), 50);
  EXPECT_DOUBLE_EQ(both.mean_return(), 50);
}

}  // namespace
}  // namespace poet
