#pragma once
// The paper's metrics of a run as JSON: what `poet-report --json` writes and the Python module's Run reads.
// Field names and order are the report's contract (README's poet-report section).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_directory/reading/coverage.h"
#include "run_directory/reading/goal_switching.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

// A difficulty level's name ("easy" ... "extremely challenging").
std::string level_name(size_t level);

// The pairs whose lineage the report shows: every solved pair at challenging or above; without one, the solved
// pair with the most ancestors (the first such).
std::vector<int> lineage_pairs(const RunSnapshot& run);

// Each shown lineage: its links, how each was solved and the transfers it took.
nlohmann::ordered_json goal_switching_json(const RunSnapshot& run, const RunMetrics& m);

// Everything: the run, the levels, counts over time, solve times, transfers, goal switching, ANNECS, coverage,
// the closest to the target, and every pair. samples_file is named when the coverage sample was written.
nlohmann::ordered_json report_json(const RunSnapshot& run, const RunMetrics& m, const Coverage& coverage,
                                   const std::string& samples_file = "");

}  // namespace poet
