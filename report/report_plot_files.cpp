#include "report/report_plot_files.h"

#include "report/report_plots.h"
#include "report/report_tables.h"
#include "report/run_pictures.h"

namespace poet {

std::vector<PlotFile> report_plot_files(const RunSnapshot& run, const RunMetrics& metrics) {
  std::vector<PlotFile> files;
  files.push_back({"scores.png", render_score_plot(PictureFormat::kPng, run)});
  files.push_back({"levels.png", render_level_plot(PictureFormat::kPng, metrics)});
  files.push_back({"annecs.png", render_annecs_plot(PictureFormat::kPng, metrics)});
  files.push_back({"frontier.png", render_frontier_plot(PictureFormat::kPng, metrics)});
  files.push_back({"phases.png", render_phase_plot(PictureFormat::kPng, metrics)});
  files.push_back({"tree.png", render_tree_plot(PictureFormat::kPng, run, metrics)});
  files.push_back(
      {"lineage.png", render_run_picture(run, {PictureKind::kLineage, PictureEncoding::kPng, deepest_pair(run)})});
  return files;
}

}  // namespace poet
