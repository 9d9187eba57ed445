#pragma once
// A suite score as the text tables the tools print: one policy's groups (finished with its 95% interval, mean
// return with its own), and one line per policy when many are compared.

#include <string>

#include "simulation/suite/course_suite.h"

namespace poet {

// Lines: the suite's name and size, a header, one line per group, then "all".
std::string suite_table(const SuiteScore& score);

// The header of a comparison of many policies on one suite, and each policy's line: finished per group and in all,
// and the mean progress and mean return over the suite. `label` is cut to 24 characters.
std::string suite_rows_header(const SuiteScore& any);
std::string suite_row(const std::string& label, const SuiteScore& score);

}  // namespace poet
