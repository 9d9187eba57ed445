#include "report/run_pictures.h"

#include <array>

#include "engine/rollout_batch.h"
#include "pictures/course_picture.h"
#include "pictures/course_stack.h"
#include "pictures/walker_pictures.h"
#include "report/pair_episode.h"
#include "report/report_plots.h"
#include "run_directory/reading/goal_switching.h"
#include "run_directory/reading/run_metrics.h"
#include "simulation/enum_names.h"

namespace poet {
namespace {

constexpr std::array<std::pair<PictureKind, std::string_view>, 9> kKinds = {{{PictureKind::kScores, "scores"},
                                                                             {PictureKind::kLevels, "levels"},
                                                                             {PictureKind::kAnnecs, "annecs"},
                                                                             {PictureKind::kTree, "tree"},
                                                                             {PictureKind::kRose, "rose"},
                                                                             {PictureKind::kCourse, "course"},
                                                                             {PictureKind::kFilmstrip, "filmstrip"},
                                                                             {PictureKind::kWalk, "walk"},
                                                                             {PictureKind::kLineage, "lineage"}}};

// The courses from the first environment down to pair's, each labelled with its pair, name, creation and solve.
Expected<std::string> render_lineage(PictureFormat format, const RunSnapshot& run, int pair) {
  if (!run.state.find(pair)) return Unexpected{"no pair " + std::to_string(pair) + " in " + run.dir.string()};
  std::vector<LabelledCourse> courses;
  for (const LineageLink& link : lineage_chain(run, compute_run_metrics(run), pair)) {
    const std::string solved = link.solved == kNone ? "unsolved" : "solved at " + std::to_string(link.solved);
    courses.push_back({Terrain::generate(run.state.find(link.pair)->env),
                       "pair " + std::to_string(link.pair) + "  " + link.env + "  created at " +
                           std::to_string(link.created) + ", " + solved});
  }
  return render_course_stack(format, courses);
}

}  // namespace

std::optional<PictureKind> picture_kind(std::string_view name) {
  for (const auto& [kind, text] : kKinds)
    if (text == name) return kind;
  return std::nullopt;
}

std::optional<PictureEncoding> picture_encoding(std::string_view extension) {
  if (extension == "png") return PictureEncoding::kPng;
  if (extension == "svg") return PictureEncoding::kSvg;
  if (extension == "gif") return PictureEncoding::kGif;
  return std::nullopt;
}

bool needs_pair(PictureKind kind) {
  return kind == PictureKind::kCourse || kind == PictureKind::kFilmstrip || kind == PictureKind::kWalk ||
         kind == PictureKind::kLineage;
}

std::string picture_kind_names() {
  std::string names;
  for (const auto& [kind, text] : kKinds) names += (names.empty() ? "" : ", ") + std::string(text);
  return names;
}

const char* mime_type(PictureEncoding encoding) {
  static constexpr std::array<std::string_view, 3> kTypes = {"image/png", "image/svg+xml", "image/gif"};
  return enum_name(encoding, kTypes, "application/octet-stream").data();
}

Expected<RolloutResult> pair_episode(const RunSnapshot& run, int pair) {
  const Pair* p = run.state.find(pair);
  if (!p) return Unexpected{"no pair " + std::to_string(pair) + " in " + run.dir.string()};
  RolloutLimits limits;
  limits.max_steps = run.state.settings.episodes.max_steps;
  limits.record_trajectory = true;
  return rollout(p->theta, p->env, run.state.settings.episodes.walker, limits);
}

std::optional<std::string> encoding_problem(const PictureRequest& request) {
  const bool gif = request.encoding == PictureEncoding::kGif;
  if (gif == (request.kind == PictureKind::kWalk)) return std::nullopt;
  return gif ? "only the walk is a GIF (the others are .png or .svg)" : "the walk is a GIF (.gif)";
}

Expected<std::string> render_run_picture(const RunSnapshot& run, const PictureRequest& request) {
  if (std::optional<std::string> problem = encoding_problem(request)) return Unexpected{*problem};
  const PictureFormat format = request.encoding == PictureEncoding::kSvg ? PictureFormat::kSvg : PictureFormat::kPng;
  switch (request.kind) {
    case PictureKind::kScores:
      return render_score_plot(format, run);
    case PictureKind::kLevels:
      return render_level_plot(format, compute_run_metrics(run));
    case PictureKind::kAnnecs:
      return render_annecs_plot(format, compute_run_metrics(run));
    case PictureKind::kTree:
      return render_tree_plot(format, run, compute_run_metrics(run));
    case PictureKind::kRose:
      return render_rose_plot(format, run);
    case PictureKind::kLineage:
      return render_lineage(format, run, request.pair);
    case PictureKind::kCourse:
    case PictureKind::kFilmstrip:
    case PictureKind::kWalk:
      break;
  }
  Expected<RolloutResult> episode = pair_episode(run, request.pair);
  if (!episode) return Unexpected{episode.error()};
  const Pair& pair = *run.state.find(request.pair);
  const Terrain terrain = Terrain::generate(pair.env);
  if (request.kind == PictureKind::kFilmstrip) return render_filmstrip(format, terrain, *episode);
  if (request.kind == PictureKind::kWalk) return render_walk_gif(terrain, *episode);
  return render_course_picture(format, terrain, *episode);
}

}  // namespace poet
