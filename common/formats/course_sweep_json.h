#pragma once
// A course sweep as JSON: what poet-eval prints for each course.

#include <nlohmann/json.hpp>

#include "simulation/course_sweep.h"

namespace poet {

// {"course", "first_seed", "episodes", "mean_return", "min_return", "max_return", "finished", "fell",
//  "timed_out", "mean_steps", "returns": [...], "steps": [...], "finished_seeds": [the seeds it finished on]}
nlohmann::json to_json(const CourseSweep& sweep);

}  // namespace poet
