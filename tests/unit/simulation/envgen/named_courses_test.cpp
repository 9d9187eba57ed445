#include "simulation/envgen/named_courses.h"

#include <gtest/gtest.h>

#include "simulation/envgen/env_distance.h"

namespace poet {
namespace {

TEST(EnvNamedCourses, EveryNameGivesAValidEncodingCarryingThatName) {
  ASSERT_EQ(course_names().size(), 5u);
  for (std::string_view name : course_names()) {
    const std::optional<EnvEncoding> e = named_course(name);
    ASSERT_TRUE(e) << name;
    EXPECT_EQ(validate(*e), std::nullopt) << name;
    EXPECT_EQ(e->name, name);
  }
  EXPECT_FALSE(named_course("Flat"));
  EXPECT_FALSE(named_course(""));
}

TEST(EnvNamedCourses, Genes) {
  EXPECT_TRUE(named_course("flat")->same_genes(EnvEncoding{}));
  EXPECT_EQ(named_course("r1")->roughness, 1.0);
  EXPECT_EQ(named_course("r3")->roughness, 3.0);
  EXPECT_FALSE(named_course("r3")->has_pits() || named_course("r3")->has_stumps());

  const EnvEncoding hard = *named_course("hard");
  EXPECT_EQ(hard.roughness, 3.0);
  EXPECT_EQ(hard.pit_gap, (Interval{2.0, 4.0}));
  EXPECT_EQ(hard.stump_width, (Interval{1.0, 2.0}));
  EXPECT_EQ(hard.stump_height, (Interval{1.5, 2.5}));
  EXPECT_EQ(hard.stump_float, (Interval{0.0, 1.0}));
  EXPECT_FALSE(hard.has_stairs());
  EXPECT_EQ(difficulty(hard), Difficulty::kChallenging);  // only the stumps pass a threshold

  const EnvEncoding hc = *named_course("hardcore-like");
  EXPECT_EQ(hc.roughness, 1.0);
  EXPECT_EQ(hc.pit_gap, (Interval{1.0, 3.0}));
  EXPECT_EQ(hc.stump_width, (Interval{1.0, 3.0}));
  EXPECT_EQ(hc.stump_height, (Interval{0.5, 2.0}));
  EXPECT_EQ(hc.stump_float, (Interval{0.0, 1.0}));
  EXPECT_EQ(hc.stair_height, (Interval{1.0, 1.0}));
  EXPECT_EQ(hc.stair_width, (Interval{4.0, 5.0}));
  EXPECT_EQ(hc.stair_steps, (Interval{3.0, 5.0}));
  EXPECT_EQ(difficulty(hc), Difficulty::kEasy);
}

}  // namespace
}  // namespace poet
