#pragma once
// poet-report's text: a run's metrics (spec §3) as the tables a person reads — the run and its counters, the
// levels, when each level was first reached, where the time went, transfers, the lineages (goal switching),
// ANNECS and the frontier, coverage and the pairs — from what the run directory library's readers computed; and
// the coverage sample as CSV. Text only, written nowhere: the caller prints or saves it.

#include <string>

#include "run_directory/reading/coverage.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"
#include "run_directory/reading/run_suite.h"

namespace poet {

// The report's table. samples_file: where the coverage sample was written, named in the coverage section ("" for
// none).
std::string report_table(const RunSnapshot& run, const RunMetrics& metrics, const Coverage& coverage,
                         const std::string& samples_file);

// The run's agents on a test suite, as the table's last section (poet-report --suite).
std::string report_suite_section(const std::string& suite_name, const RunSuite& scores);

// The coverage sample (level, the five parameters, the distance to the nearest solved environment, empty when none
// was solved) as CSV, every digit kept (poet-report --coverage-samples).
std::string coverage_samples_csv(const Coverage& coverage);

// The pair whose lineage the table shows last (the first pair when it shows none): the lineage the plots draw.
int deepest_pair(const RunSnapshot& run);

}  // namespace poet
