#include "report/report_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <utility>

#include "pictures/chart.h"

namespace poet {
namespace {

constexpr std::array<Rgb, kLevels> kLevelColours = {
    {{0.35, 0.35, 0.35}, {0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.839, 0.153, 0.157}}};

std::string short_name(const std::string& name, size_t max = 22) {
  return name.size() <= max ? name : name.substr(0, max - 1) + "…";
}

// A chart of how many environments there were at each iteration, from zero.
Chart counts_over_iterations(std::string title) {
  Chart chart;
  chart.title = std::move(title);
  chart.x_label = "iteration";
  chart.y_label = "environments";
  chart.y_min = 0;
  chart.integer_x = true;
  return chart;
}

}  // namespace

Expected<std::string> render_score_plot(PictureFormat format, const RunSnapshot& run) {
  Chart chart;
  chart.title = "Evaluation score of each pair's agent on its own environment";
  chart.x_label = "iteration";
  chart.y_label = "score";
  chart.integer_x = true;
  chart.reference_line = {
      {run.state.settings.poet.solved_score,
       "solved (finished and ≥ " + std::to_string(static_cast<int>(run.state.settings.poet.solved_score)) + ")"}};
  std::map<int, size_t> series_of;
  for (const Pair& p : run.state.pairs) {
    series_of[p.id] = chart.series.size();
    chart.series.push_back({"#" + std::to_string(p.id) + " " + short_name(p.env.encoding.name),
                            {},
                            palette_colour(chart.series.size()),
                            ChartSeries::Line::kSolid,
                            false,
                            1.4});
  }
  for (const StatsRow& row : run.stats) {
    const auto found = series_of.find(row.pair);
    if (found != series_of.end()) chart.series[found->second].points.emplace_back(row.iteration, row.score);
  }
  // a legend entry per pair while they fit; beyond that the colours repeat and the legend would mislead
  if (chart.series.size() > 20)
    for (ChartSeries& s : chart.series) s.label.clear();
  return render_picture(format, 1000, 520, [&](cairo_t* cr) { draw_chart(cr, 0, 0, 1000, 520, chart); });
}

Expected<std::string> render_level_plot(PictureFormat format, const RunMetrics& metrics) {
  Chart chart = counts_over_iterations("Environments per difficulty level (cumulative)");
  struct Kind {
    const char* name;
    std::function<int64_t(const LevelCounts&, size_t)> count;
    ChartSeries::Line line;
    double width;
  };
  const Kind kinds[] = {
      {"created", [](const LevelCounts& c, size_t l) { return c.created[l]; }, ChartSeries::Line::kDashed, 1.2},
      {"admitted", [](const LevelCounts& c, size_t l) { return c.admitted[l]; }, ChartSeries::Line::kDotted, 1.6},
      {"solved", [](const LevelCounts& c, size_t l) { return c.solved[l]; }, ChartSeries::Line::kSolid, 3.0},
  };
  for (size_t level = 0; level < kLevels; ++level) {
    for (const Kind& kind : kinds) {
      if (kind.count(metrics.total, level) == 0) continue;
      ChartSeries s{std::string(kind.name) + ", " + std::string(to_string(static_cast<Difficulty>(level))),
                    {},
                    kLevelColours[level],
                    kind.line,
                    true,
                    kind.width};
      for (const LevelTimePoint& point : metrics.over_time)
        s.points.emplace_back(point.iteration, static_cast<double>(kind.count(point.total, level)));
      chart.series.push_back(std::move(s));
    }
  }
  return render_picture(format, 1000, 480, [&](cairo_t* cr) { draw_chart(cr, 0, 0, 1000, 480, chart); });
}

Expected<std::string> render_frontier_plot(PictureFormat format, const RunMetrics& metrics) {
  Chart chart;
  chart.title = "Obstacle frontier: hardest solved (solid), admitted (dashed); roughness / 4.5, gap / 6.0, stump / 2.4";
  chart.x_label = "iteration";
  chart.y_label = "value / threshold";
  chart.y_min = 0;
  chart.integer_x = true;
  chart.reference_line = {{1.0, "Table 1's condition"}};
  const struct {
    const char* label;
    double threshold;
    Rgb colour;
  } measures[3] = {{"roughness", kChallengingRoughness, kLevelColours[1]},
                   {"gap top", kChallengingGap, kLevelColours[2]},
                   {"stump top", kChallengingStumpHeight, kLevelColours[3]}};
  double highest = 1.0;
  for (size_t k = 0; k < 3; ++k) {
    ChartSeries solved{
        std::string(measures[k].label) + ", solved", {}, measures[k].colour, ChartSeries::Line::kSolid, true, 2.4};
    ChartSeries admitted{
        std::string(measures[k].label) + ", admitted", {}, measures[k].colour, ChartSeries::Line::kDashed, true, 1.2};
    for (const FrontierPoint& f : metrics.frontier_over_time) {
      solved.points.emplace_back(f.iteration, f.solved[k] / measures[k].threshold);
      admitted.points.emplace_back(f.iteration, f.admitted[k] / measures[k].threshold);
      highest = std::max(highest, f.admitted[k] / measures[k].threshold);
    }
    chart.series.push_back(std::move(solved));
    chart.series.push_back(std::move(admitted));
  }
  chart.y_max = highest * 1.1;  // the condition's line inside the frame
  return render_picture(format, 1000, 460, [&](cairo_t* cr) { draw_chart(cr, 0, 0, 1000, 460, chart); });
}

Expected<std::string> render_phase_plot(PictureFormat format, const RunMetrics& metrics) {
  Chart chart;
  chart.title =
      metrics.phase_blocks.empty()
          ? "Where the time went: no wall times in this run directory"
          : "Where the time went: share of each block's wall time, phases stacked (the rest: between iterations)";
  chart.x_label = "iteration";
  chart.y_label = "share of wall time";
  chart.y_min = 0;
  chart.y_max = 1;
  chart.integer_x = true;
  const char* labels[] = {"reproduction", "+ ES steps", "+ evaluations", "+ transfer"};
  for (size_t k = 0; k < kPhaseNames.size(); ++k) {
    ChartSeries stacked{labels[k], {}, kLevelColours[k], ChartSeries::Line::kSolid, true, 2.0};
    for (const PhaseBlock& b : metrics.phase_blocks) {
      if (b.timed == 0 || b.wall_s <= 0) continue;
      double below = 0;
      for (size_t j = 0; j <= k; ++j) below += b.phases[j];
      stacked.points.emplace_back(b.first, below / b.wall_s);
      stacked.points.emplace_back(b.last + 1, below / b.wall_s);
    }
    chart.series.push_back(std::move(stacked));
  }
  return render_picture(format, 1000, 460, [&](cairo_t* cr) { draw_chart(cr, 0, 0, 1000, 460, chart); });
}

Expected<std::string> render_annecs_plot(PictureFormat format, const RunMetrics& metrics) {
  Chart chart = counts_over_iterations(
      "ANNECS: at admission (children solved, counted when solved) and at archiving (retired once solved)");
  ChartSeries admission{"at admission", {}, kLevelColours[1], ChartSeries::Line::kSolid, true, 2.4};
  ChartSeries archiving{"at archiving", {}, kLevelColours[2], ChartSeries::Line::kDashed, true, 2.0};
  for (size_t t = 0; t < metrics.annecs_over_time.size(); ++t) {
    admission.points.emplace_back(static_cast<double>(t), metrics.annecs_over_time[t].at_admission);
    archiving.points.emplace_back(static_cast<double>(t), metrics.annecs_over_time[t].at_archiving);
  }
  chart.series = {std::move(admission), std::move(archiving)};
  return render_picture(format, 1000, 420, [&](cairo_t* cr) { draw_chart(cr, 0, 0, 1000, 420, chart); });
}

namespace {

// The tree plot's geometry: a row per pair, iterations across.
struct TreeLayout {
  double row_height = 20, top = 46, left = 150, right_margin = 24, width = 1100;
  double height = 0;
  double last = 1;         // the axis's last iteration
  std::map<int, int> row;  // pair id → row

  double px(double iteration) const { return left + iteration / last * (width - left - right_margin); }
  double py(int id) const { return top + row_height * (row.at(id) + 0.5); }
};

// Rows in depth-first order from the roots, children in creation order, so each subtree is a block of rows.
std::map<int, int> tree_rows(const RunState& state) {
  std::map<int, std::vector<int>> children;
  std::vector<int> roots;
  for (const Pair& p : state.pairs) {
    if (p.parent_id == kNone || !state.find(p.parent_id))
      roots.push_back(p.id);
    else
      children[p.parent_id].push_back(p.id);
  }
  std::map<int, int> row;
  std::function<void(int)> place = [&](int id) {
    row[id] = static_cast<int>(row.size());
    for (int child : children[id]) place(child);
  };
  for (int id : roots) place(id);
  return row;
}

TreeLayout tree_layout(const RunState& state, const RunMetrics& metrics) {
  TreeLayout layout;
  layout.row = tree_rows(state);
  layout.height = layout.top + layout.row_height * std::max<size_t>(1, state.pairs.size()) + 56;
  layout.last = std::max(1, metrics.iterations_done);
  return layout;
}

void draw_iteration_axis(cairo_t* cr, const TreeLayout& layout) {
  for (double t : nice_ticks(0, layout.last, 8, true)) {
    cairo_set_source_rgb(cr, 0.92, 0.92, 0.92);
    cairo_set_line_width(cr, 1);
    cairo_move_to(cr, std::round(layout.px(t)) + 0.5, layout.top);
    cairo_line_to(cr, std::round(layout.px(t)) + 0.5, layout.height - 40);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    draw_text(cr, std::to_string(static_cast<long long>(t)), layout.px(t), layout.height - 26, 11, 0.5);
  }
  draw_text(cr, "iteration", (layout.left + layout.width) / 2, layout.height - 8, 12, 0.5);
}

// A pair's row: the link from its parent, its lifeline and its node with the name.
void draw_pair_row(cairo_t* cr, const TreeLayout& layout, const Pair& p, int iterations_done) {
  const double y = layout.py(p.id);
  const double start = layout.px(p.created_iteration);
  const double end = layout.px(p.active() ? iterations_done : p.retired_iteration);
  const int level = static_cast<int>(difficulty(p.env.encoding));
  // parent link: an elbow from the parent's row down to the child's start
  if (p.parent_id != kNone && layout.row.count(p.parent_id)) {
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, 1.2);
    cairo_move_to(cr, start, layout.py(p.parent_id));
    cairo_line_to(cr, start, y);
    cairo_stroke(cr);
  }
  // lifeline: grey while unsolved, green from the first solve
  cairo_set_line_width(cr, 6);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_source_rgb(cr, 0.78, 0.78, 0.78);
  cairo_move_to(cr, start, y);
  cairo_line_to(cr, std::max(end, start + 2), y);
  cairo_stroke(cr);
  if (p.solved()) {
    cairo_set_source_rgb(cr, 0.2, 0.65, 0.25);
    cairo_move_to(cr, layout.px(p.first_solved_iteration), y);
    cairo_line_to(cr, std::max(end, layout.px(p.first_solved_iteration) + 2), y);
    cairo_stroke(cr);
  }
  // node: coloured by difficulty level
  set_colour(cr, kLevelColours[static_cast<size_t>(level)]);
  cairo_arc(cr, start, y, 4.5, 0, 2 * M_PI);
  cairo_fill(cr);
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  draw_text(cr, "#" + std::to_string(p.id) + " " + short_name(p.env.encoding.name, 18), layout.left - 8, y + 4, 10, 1);
}

// An accepted transfer: a curve from the source's row to the target's, with an arrow head at the target.
void draw_transfer(cairo_t* cr, const TreeLayout& layout, const AcceptedTransfer& t) {
  const double x = layout.px(t.iteration), y0 = layout.py(t.source), y1 = layout.py(t.target);
  const double bend = std::min(40.0, std::abs(y1 - y0) / 3 + 8);
  cairo_set_source_rgba(cr, 0.95, 0.5, 0.05, 0.85);
  cairo_set_line_width(cr, 1.4);
  cairo_move_to(cr, x, y0);
  cairo_curve_to(cr, x + bend, y0, x + bend, y1, x + 3, y1);
  cairo_stroke(cr);
  const double dir = y1 > y0 ? -1 : 1;
  cairo_move_to(cr, x + 3, y1);
  cairo_line_to(cr, x + 10, y1 + 3 * dir - 2);
  cairo_line_to(cr, x + 10, y1 - 3 * dir + 2);
  cairo_close_path(cr);
  cairo_fill(cr);
}

void draw_level_legend(cairo_t* cr, double height) {
  double lx = 12;
  for (size_t level = 0; level < kLevels; ++level) {
    set_colour(cr, kLevelColours[level]);
    cairo_arc(cr, lx + 4, height - 12, 4, 0, 2 * M_PI);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    const std::string name(to_string(static_cast<Difficulty>(level)));
    draw_text(cr, name, lx + 12, height - 8, 10);
    lx += 24 + 5.5 * static_cast<double>(name.size());
  }
}

}  // namespace

Expected<std::string> render_tree_plot(PictureFormat format, const RunSnapshot& run, const RunMetrics& metrics) {
  const TreeLayout layout = tree_layout(run.state, metrics);
  return render_picture(format, layout.width, layout.height, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    draw_text(cr, "Environment tree: rows are pairs from creation to retirement (green once solved)", layout.width / 2,
              20, 14, 0.5, true);
    draw_text(cr, "grey links: parent → child environment; orange arrows: accepted transfers (source → target)",
              layout.width / 2, 36, 11, 0.5);
    draw_iteration_axis(cr, layout);
    for (const Pair& p : run.state.pairs) draw_pair_row(cr, layout, p, metrics.iterations_done);
    // transfers, drawn last so they stay visible
    for (const AcceptedTransfer& t : metrics.accepted_transfers)
      if (layout.row.count(t.source) && layout.row.count(t.target)) draw_transfer(cr, layout, t);
    draw_level_legend(cr, layout.height);
  });
}

namespace {

// One rose of the paper's Figure 3: the five encoding values on spokes scaled to §1.4's maxima (8, 8, 8, 3, 3),
// with each environment a closed polygon, drawn in order (the last on top).
struct RosePolygon {
  EnvVector e{};
  Rgb colour;
  double fill_alpha = 0.35;
};

void draw_rose(cairo_t* cr, double cx, double cy, double radius, const std::vector<RosePolygon>& polygons,
               double label_size) {
  static const char* const kAxes[5] = {"roughness", "gap lo", "gap hi", "stump lo", "stump hi"};
  const auto corner = [&](size_t axis, double fraction) {
    const double angle = -M_PI / 2 + 2 * M_PI * static_cast<double>(axis) / 5;
    return std::pair{cx + std::cos(angle) * radius * fraction, cy + std::sin(angle) * radius * fraction};
  };
  // rings and spokes
  cairo_set_line_width(cr, 0.8);
  cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  for (double ring : {0.25, 0.5, 0.75, 1.0}) {
    for (size_t a = 0; a <= 5; ++a) {
      const auto [x, y] = corner(a % 5, ring);
      a == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    cairo_stroke(cr);
  }
  for (size_t a = 0; a < 5; ++a) {
    const auto [x, y] = corner(a, 1.0);
    cairo_move_to(cr, cx, cy);
    cairo_line_to(cr, x, y);
    cairo_stroke(cr);
    const auto [lx, ly] = corner(a, 1.28);
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
    draw_text(cr, kAxes[a], lx, ly + 3, label_size, 0.5);
    cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  }
  for (const RosePolygon& polygon : polygons) {
    for (size_t a = 0; a <= 5; ++a) {
      const auto [x, y] = corner(a % 5, std::clamp(polygon.e[a % 5] / kEnvVectorMax[a % 5], 0.0, 1.0));
      a == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    set_colour(cr, polygon.colour, polygon.fill_alpha);
    cairo_fill_preserve(cr);
    set_colour(cr, polygon.colour);
    cairo_set_line_width(cr, 1.5);
    cairo_stroke(cr);
  }
}

std::string vector_text(const EnvVector& e) {
  char text[96];
  std::snprintf(text, sizeof text, "r %.1f, gaps %.1f–%.1f, stumps %.1f–%.1f", e[0], e[1], e[2], e[3], e[4]);
  return text;
}

}  // namespace

Expected<std::string> render_rose_plot(PictureFormat format, const RunSnapshot& run) {
  const RunState& state = run.state;
  const int n = static_cast<int>(state.pairs.size());
  const int columns = std::min(std::max(n, 1), 6);
  const int rows = std::max(1, (n + columns - 1) / columns);
  const double cell = 180, top = 40;
  const double width = columns * cell, height = top + rows * cell;
  return render_picture(format, width, height, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    draw_text(cr, "Environment parameters per pair (axes scaled to the maxima 8, 8, 8, 3, 3; green: solved)", width / 2,
              22, 13, 0.5, true);
    for (int i = 0; i < n; ++i) {
      const Pair& p = state.pairs[static_cast<size_t>(i)];
      const double cx = (i % columns + 0.5) * cell, cy = top + (i / columns + 0.5) * cell - 4;
      const Rgb colour = p.solved() ? Rgb{0.2, 0.65, 0.25} : Rgb{0.55, 0.55, 0.55};
      draw_rose(cr, cx, cy, cell * 0.32, {{env_vector(p.env.encoding), colour}}, 8.5);
      cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
      draw_text(
          cr, "#" + std::to_string(p.id) + " " + short_name(p.env.encoding.name, 20) + (p.active() ? "" : " (retired)"),
          cx, cy + cell * 0.47, 9.5, 0.5, true);
    }
  });
}

Expected<std::string> render_controls_rose(PictureFormat format, const ControlsRose& rose) {
  const double width = 720, height = 470, cx = 215, cy = 250, radius = 150;
  const Rgb red{0.84, 0.15, 0.16}, blue{0.12, 0.47, 0.71};
  return render_picture(format, width, height, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    draw_text(cr, rose.title, width / 2, 24, 13, 0.5, true);
    std::vector<RosePolygon> polygons;
    for (const ControlStage& c : rose.controls)
      if (c.closest_solved) polygons.push_back({*c.closest_solved, blue, 0.12});
    polygons.push_back({rose.poet, red, 0.18});  // on top: the environment POET created and solved
    draw_rose(cr, cx, cy, radius, polygons, 10);
    // the legend: POET's environment, then each control with its closest solved stage and distance
    double y = 70;
    const auto line = [&](Rgb colour, const std::string& head, const std::string& detail) {
      set_colour(cr, colour);
      cairo_rectangle(cr, 430, y - 9, 12, 12);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
      draw_text(cr, head, 450, y + 1, 10.5, 0, true);
      draw_text(cr, detail, 450, y + 15, 9.5);
      y += 38;
    };
    line(red, "POET: " + short_name(rose.poet_label, 34), vector_text(rose.poet));
    for (const ControlStage& c : rose.controls) {
      char distance[48];
      if (c.distance)
        std::snprintf(distance, sizeof distance, "distance %.3f", *c.distance);
      else
        std::snprintf(distance, sizeof distance, "nothing solved");
      line(c.closest_solved ? blue : Rgb{0.7, 0.7, 0.7}, short_name(c.label, 40),
           std::string(distance) + (c.closest_solved ? ": " + vector_text(*c.closest_solved) : ""));
    }
  });
}

}  // namespace poet
