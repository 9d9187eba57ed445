#include "report/learning_curves.h"

#include <array>
#include <functional>
#include <map>
#include <sstream>
#include <string_view>

#include "common/plumbing/text_file.h"
#include "common/text/csv_fields.h"
#include "pictures/chart.h"

namespace poet {
namespace {

constexpr std::array<const char*, 6> kColumns = {"es_step", "score", "finished", "env_steps", "rollouts", "wall_s"};
// A curve is a line per ES step, some 100 bytes each: 64 MB is over half a million steps, and a file past it is
// refused before it is read whole.
constexpr std::uintmax_t kMaxCurveBytes = std::uintmax_t{64} << 20;
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

// The next line of in without its line end, whether "\n" or "\r\n" (a CSV saved on Windows).
bool next_line(std::istringstream& in, std::string& line) {
  if (!std::getline(in, line)) return false;
  if (line.ends_with('\r')) line.pop_back();
  return true;
}

std::string where(const std::string& source, size_t line) { return source + ":" + std::to_string(line); }

}  // namespace

Expected<LearningCurve> parse_learning_curve(const std::string& text, const std::string& source) {
  // a byte-order mark, as spreadsheet programs write before UTF-8, is not part of the first column's name
  std::istringstream in(text.starts_with(kUtf8Bom) ? text.substr(kUtf8Bom.size()) : text);
  std::string line;
  if (!next_line(in, line)) return Unexpected{source + ": empty, expected a header line"};
  std::map<std::string, size_t> column_of;
  const std::vector<std::string> header = csv_fields(line);
  for (size_t i = 0; i < header.size(); ++i) column_of[header[i]] = i;
  std::array<size_t, kColumns.size()> at{};
  for (size_t c = 0; c < kColumns.size(); ++c) {
    const auto found = column_of.find(kColumns[c]);
    if (found == column_of.end()) return Unexpected{where(source, 1) + ": no column " + kColumns[c]};
    at[c] = found->second;
  }

  LearningCurve curve;
  for (size_t number = 2; next_line(in, line); ++number) {
    if (line.empty()) continue;
    const std::vector<std::string> fields = csv_fields(line);
    if (fields.size() != header.size())
      return Unexpected{where(source, number) + ": " + std::to_string(fields.size()) + " fields, the header has " +
                        std::to_string(header.size())};
    CurvePoint p;
    const auto bad = [&](size_t c) {
      return Unexpected{where(source, number) + ": " + kColumns[c] + ": not a number: \"" + fields[at[c]] + "\""};
    };
    if (!parse_field(fields[at[0]], p.es_step) || p.es_step < 0) return bad(0);
    if (!parse_field(fields[at[1]], p.score)) return bad(1);
    const std::string& finished = fields[at[2]];
    if (finished != "true" && finished != "false")
      return Unexpected{where(source, number) + ": finished: expected true or false, got \"" + finished + "\""};
    p.finished = finished == "true";
    if (!parse_field(fields[at[3]], p.env_steps) || p.env_steps < 0) return bad(3);
    if (!parse_field(fields[at[4]], p.rollouts) || p.rollouts < 0) return bad(4);
    // a step the curve script saw no time for has an empty wall_s; it takes its predecessor's
    if (fields[at[5]].empty())
      p.wall_s = curve.points.empty() ? 0 : curve.points.back().wall_s;
    else if (!parse_field(fields[at[5]], p.wall_s) || p.wall_s < 0)
      return bad(5);
    if (!curve.points.empty() && p.es_step <= curve.points.back().es_step)
      return Unexpected{where(source, number) + ": es_step " + std::to_string(p.es_step) + " after " +
                        std::to_string(curve.points.back().es_step) + ": steps must increase"};
    curve.points.push_back(p);
  }
  if (curve.points.empty()) return Unexpected{source + ": no steps after the header"};
  return curve;
}

Expected<LearningCurve> read_learning_curve(const std::string& path) {
  Expected<std::string> text = read_text_file(path, kMaxCurveBytes);
  if (!text) return Unexpected{path + ": " + text.error()};
  return parse_learning_curve(*text, path);
}

const CurvePoint* first_solved(const LearningCurve& curve, double solved_score) {
  for (const CurvePoint& p : curve.points)
    if (p.finished && p.score >= solved_score) return &p;
  return nullptr;
}

Expected<std::string> render_learning_curves(PictureFormat format, std::span<const LearningCurve> curves,
                                             double solved_score) {
  struct Axis {
    const char* title;
    const char* label;
    std::function<double(const CurvePoint&)> x;
  };
  const std::array<Axis, 3> axes = {{
      {"Evaluation score against ES steps", "ES step", [](const CurvePoint& p) { return double(p.es_step); }},
      {"… against environment steps", "environment steps (millions)",
       [](const CurvePoint& p) { return p.env_steps / 1e6; }},
      {"… against wall time", "wall time (minutes)", [](const CurvePoint& p) { return p.wall_s / 60; }},
  }};
  constexpr double kWidth = 1000, kChartHeight = 420;
  return render_picture(format, kWidth, kChartHeight * axes.size(), [&](cairo_t* cr) {
    for (size_t a = 0; a < axes.size(); ++a) {
      Chart chart;
      chart.title = axes[a].title;
      chart.x_label = axes[a].label;
      chart.y_label = "score";
      chart.integer_x = a == 0;
      chart.reference_line = {{solved_score, "solved (finished and ≥ " + std::to_string(int(solved_score)) + ")"}};
      for (size_t c = 0; c < curves.size(); ++c) {
        ChartSeries series{curves[c].label, {}, palette_colour(c), ChartSeries::Line::kSolid, false, 1.6};
        for (const CurvePoint& p : curves[c].points) series.points.emplace_back(axes[a].x(p), p.score);
        chart.series.push_back(std::move(series));
      }
      draw_chart(cr, 0, kChartHeight * a, kWidth, kChartHeight, chart);
    }
  });
}

}  // namespace poet
