#pragma once
// A policy's score on a test suite as JSON: what poet-eval --suite --json writes, per group the figures it prints
// and every episode (course, encoding, terrain seed, return, steps, how it ended).

#include <nlohmann/json.hpp>

#include "simulation/suite/course_suite.h"

namespace poet {

// {"suite", "episodes", "finished", "finished_fraction", "mean_return", "mean_progress",
//  "groups": [{"group", "episodes", "finished", "finished_fraction", "finished_interval": [lo, hi],
//              "mean_return", "mean_progress", "return_sd", "mean_return_half_width",
//              "courses": [{"course", "config": {...}, "episodes": [{"seed", "return", "steps", "progress",
//                                                                   "finished", "fell"}]}]}]}
// `score` must come from run_suite on `suite`.
nlohmann::json to_json(const SuiteScore& score, const CourseSuite& suite);

// The same without the episodes: one line of a table in JSON.
nlohmann::json summary_json(const SuiteScore& score);

}  // namespace poet
