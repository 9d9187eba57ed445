#pragma once
// The pictures poet-report --plots writes, each with its file name: the run's plots (report_plots.h) and the
// courses along the lineage the table shows last (run_pictures.h), as PNG. Drawn, not written: the caller saves them.

#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

struct PlotFile {
  std::string name;             // "scores.png", ...
  Expected<std::string> bytes;  // or why it could not be drawn
};

// scores, levels, annecs, frontier, phases, tree and lineage, in that order.
std::vector<PlotFile> report_plot_files(const RunSnapshot& run, const RunMetrics& metrics);

}  // namespace poet
