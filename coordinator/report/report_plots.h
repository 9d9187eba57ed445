#pragma once
// The pictures of a run, drawn with cairo as PNG or SVG bytes: each pair's evaluation score over iterations;
// environments created, admitted and solved per difficulty level over iterations; ANNECS over iterations in both
// definitions (poet/annecs.h), a named line each; the environment tree — each
// pair a row from its creation to its retirement (green once solved), parent → child links, and accepted
// transfers as arrows from source to target at their iteration; and the paper's rose plots, one per pair, of its
// environment's parameters. Each returns the bytes or an error message.

#include <string>

#include "canvas.h"
#include "expected.h"
#include "report/run_metrics.h"
#include "report/run_snapshot.h"

namespace poet {

Expected<std::string> render_score_plot(PictureFormat format, const RunSnapshot& run);
Expected<std::string> render_level_plot(PictureFormat format, const RunMetrics& metrics);
Expected<std::string> render_annecs_plot(PictureFormat format, const RunMetrics& metrics);
Expected<std::string> render_tree_plot(PictureFormat format, const RunSnapshot& run, const RunMetrics& metrics);
Expected<std::string> render_rose_plot(PictureFormat format, const RunSnapshot& run);

}  // namespace poet
