#pragma once
// The pictures of a run, drawn with cairo (PNG, or SVG for any other extension): each pair's evaluation score
// over iterations; environments created, admitted and solved per difficulty level over iterations; and the
// environment tree — each pair a row from its creation to its retirement (green once solved), parent → child
// links, and accepted transfers as arrows from source to target at their iteration. Each returns an error
// message naming the file, or empty.

#include <string>

#include "report/run_metrics.h"
#include "report/run_snapshot.h"

namespace poet {

std::string write_score_plot(const std::string& path, const RunSnapshot& run);
std::string write_level_plot(const std::string& path, const RunSnapshot& run, const RunMetrics& metrics);
std::string write_tree_plot(const std::string& path, const RunSnapshot& run, const RunMetrics& metrics);

}  // namespace poet
