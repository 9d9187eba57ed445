#pragma once
// The pictures of a run, drawn with cairo as PNG or SVG bytes: each pair's evaluation score over iterations;
// environments created, admitted and solved per difficulty level over iterations; the obstacle frontier over
// iterations; ANNECS over iterations in both definitions (poet/annecs.h), a named line each; the environment tree —
// each pair a row from its creation to its retirement (green once solved), parent → child links, and accepted transfers
// as arrows from source to target at their iteration; and the paper's rose plots, one per pair, of its environment's
// parameters; and Figure 3's rose for one target: POET's environment in red, the closest-to-target environment each
// control run solved in blue. Each returns the bytes or an error message.

#include <optional>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "pictures/canvas.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

Expected<std::string> render_score_plot(PictureFormat format, const RunSnapshot& run);
Expected<std::string> render_level_plot(PictureFormat format, const RunMetrics& metrics);
Expected<std::string> render_annecs_plot(PictureFormat format, const RunMetrics& metrics);
// Each of Table 1's measures (roughness, gap top, stump top), the hardest solved and admitted by each iteration,
// divided by its threshold, so that 1 is the condition.
Expected<std::string> render_frontier_plot(PictureFormat format, const RunMetrics& metrics);
// Where the time went: each block's share of wall time per phase, stacked (reproduction at the bottom, then ES
// steps, evaluations, transfer; the rest up to 1 is the time between iterations). A run without wall times draws
// an empty frame that says so.
Expected<std::string> render_phase_plot(PictureFormat format, const RunMetrics& metrics);
Expected<std::string> render_tree_plot(PictureFormat format, const RunSnapshot& run, const RunMetrics& metrics);
Expected<std::string> render_rose_plot(PictureFormat format, const RunSnapshot& run);

// A control run's closest-to-target solved environment (none when it solved nothing) and its normalised distance.
struct ControlStage {
  std::string label;
  std::optional<EnvVector> closest_solved;
  std::optional<double> distance;
};
struct ControlsRose {
  std::string title;
  std::string poet_label;  // the environment's name
  EnvVector poet{};
  std::vector<ControlStage> controls;
};
Expected<std::string> render_controls_rose(PictureFormat format, const ControlsRose& rose);

}  // namespace poet
