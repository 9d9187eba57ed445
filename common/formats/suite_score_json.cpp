#include "common/formats/suite_score_json.h"

#include "common/formats/envgen/env_json.h"

namespace poet {
namespace {

nlohmann::json group_summary(const GroupScore& g) {
  const auto [lo, hi] = g.finished_interval();
  return {{"group", g.group},
          {"episodes", g.episodes.size()},
          {"finished", g.finished()},
          {"finished_fraction", g.finished_fraction()},
          {"finished_interval", {lo, hi}},
          {"mean_return", g.mean_return()},
          {"mean_progress", g.mean_progress()},
          {"return_sd", g.return_sd()},
          {"mean_return_half_width", g.mean_return_half_width()}};
}

}  // namespace

nlohmann::json summary_json(const SuiteScore& score) {
  nlohmann::json groups = nlohmann::json::array();
  for (const GroupScore& g : score.groups) groups.push_back(group_summary(g));
  return {{"suite", score.suite},
          {"episodes", score.episodes()},
          {"finished", score.finished()},
          {"finished_fraction", score.finished_fraction()},
          {"mean_return", score.mean_return()},
          {"mean_progress", score.mean_progress()},
          {"groups", groups}};
}

nlohmann::json to_json(const SuiteScore& score, const CourseSuite& suite) {
  nlohmann::json doc = summary_json(score);
  for (size_t g = 0; g < score.groups.size(); ++g) {
    nlohmann::json courses = nlohmann::json::array();
    size_t next = 0;
    for (const SuiteCourse& c : suite.groups.at(g).courses) {
      nlohmann::json episodes = nlohmann::json::array();
      for (uint32_t seed : c.seeds) {
        const RolloutResult& e = score.groups[g].episodes.at(next++);
        episodes.push_back({{"seed", seed},
                            {"return", e.total_reward},
                            {"steps", e.steps},
                            {"progress", progress(e)},
                            {"finished", e.finished},
                            {"fell", e.fell}});
      }
      courses.push_back(
          {{"course", c.encoding.name}, {"config", encoding_to_json(c.encoding)}, {"episodes", episodes}});
    }
    doc["groups"][g]["courses"] = courses;
  }
  return doc;
}

}  // namespace poet
