// The walkers shipped for how they do on a held-out test suite (data/walkers/generalists.json, written by
// experiments/ship_generalist.sh): each replays the manifest's subset of its suite episodes — every one it finished
// and each group's first two — to the recorded outcome, steps and return, and the recorded figures are those
// of a suite run (counts within the group's size, the finished subset among them).

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/formats/policy/policy_file.h"
#include "simulation/rollout.h"
#include "simulation/suite/course_suite.h"
#include "walker_manifest.h"

namespace poet {
namespace {

const SuiteCourse* find_course(const CourseSuite& suite, const std::string& group, const std::string& course) {
  for (const SuiteGroup& g : suite.groups) {
    if (g.name != group) continue;
    for (const SuiteCourse& c : g.courses) {
      if (c.encoding.name == course) return &c;
    }
  }
  return nullptr;
}

TEST(GeneralistWalkers, EachReplaysItsSuiteEpisodes) {
  const std::vector<test::ManifestWalker> manifest = test::read_walker_manifest("generalists.json");
  ASSERT_FALSE(manifest.empty()) << "data/walkers/generalists.json is missing or empty";
  for (const auto& [name, entry, walker] : manifest) {
    ASSERT_TRUE(walker) << name << ": " << walker.error();
    const std::optional<CourseSuite> suite = named_suite(entry.at("suite").get<std::string>());
    ASSERT_TRUE(suite) << name << ": unknown suite " << entry.at("suite");

    std::map<std::string, int> finished_in_replay;
    for (const nlohmann::json& episode : entry.at("replay")) {
      const std::string group = episode.at("group");
      const std::string course_name = episode.at("course");
      const SuiteCourse* course = find_course(*suite, group, course_name);
      ASSERT_NE(course, nullptr) << name << ": no course " << course_name << " in " << group;
      const uint32_t seed = episode.at("seed");
      ASSERT_NE(std::find(course->seeds.begin(), course->seeds.end(), seed), course->seeds.end())
          << name << ": " << course_name << " is not run on terrain seed " << seed;
      const RolloutResult r = rollout(walker->params, EnvDef{course->encoding, seed});
      const std::string where = name + " on " + course_name + ", terrain seed " + std::to_string(seed);
      EXPECT_EQ(r.finished, episode.at("finished").get<bool>()) << where;
      EXPECT_EQ(r.steps, episode.at("steps").get<int>()) << where;
      EXPECT_NEAR(r.total_reward, episode.at("return").get<double>(), 1e-6) << where;
      finished_in_replay[group] += r.finished ? 1 : 0;
    }

    const nlohmann::json& figures = entry.at("figures");
    ASSERT_EQ(figures.size(), suite->groups.size()) << name;
    int finished = 0;
    for (size_t i = 0; i < figures.size(); ++i) {
      const SuiteGroup& group = suite->groups[i];
      EXPECT_EQ(figures[i].at("group").get<std::string>(), group.name) << name;
      EXPECT_EQ(figures[i].at("episodes").get<int>(), group.episodes()) << name << ", " << group.name;
      // The replay holds every finished episode, so it accounts for the group's count exactly.
      EXPECT_EQ(figures[i].at("finished").get<int>(), finished_in_replay[group.name]) << name << ", " << group.name;
      const double progress = figures[i].at("mean_progress");
      EXPECT_GE(progress, 0.0);
      EXPECT_LE(progress, 1.0);
      finished += figures[i].at("finished").get<int>();
    }
    EXPECT_GT(finished, 0) << name << " is shipped for the courses it finishes";
  }
}

}  // namespace
}  // namespace poet
