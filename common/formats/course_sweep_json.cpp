#include "common/formats/course_sweep_json.h"

namespace poet {

nlohmann::json to_json(const CourseSweep& s) {
  nlohmann::json returns = nlohmann::json::array(), steps = nlohmann::json::array();
  nlohmann::json finished_seeds = nlohmann::json::array();
  for (size_t i = 0; i < s.episodes.size(); ++i) {
    const RolloutResult& e = s.episodes[i];
    returns.push_back(e.total_reward);
    steps.push_back(e.steps);
    if (e.finished) finished_seeds.push_back(s.first_seed + static_cast<uint32_t>(i));
  }
  return {{"course", s.course},
          {"first_seed", s.first_seed},
          {"episodes", s.episodes.size()},
          {"mean_return", s.mean_return()},
          {"min_return", s.min_return()},
          {"max_return", s.max_return()},
          {"finished", s.finished()},
          {"fell", s.fell()},
          {"timed_out", s.timed_out()},
          {"mean_steps", s.mean_steps()},
          {"returns", returns},
          {"steps", steps},
          {"finished_seeds", finished_seeds}};
}

}  // namespace poet
