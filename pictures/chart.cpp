#include "pictures/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace poet {

std::vector<double> nice_ticks(double lo, double hi, int target, bool integer) {
  // Any bounds give a few finite ticks: a bound that is not finite, or a span too narrow for a double to step
  // through (a constant near 1e300) or too wide to subtract (±1e308), is brought back to one it can.
  const int n = std::max(1, target);
  if (!std::isfinite(lo)) lo = 0;
  if (!std::isfinite(hi) || !(hi > lo)) hi = lo + std::max(1.0, std::abs(lo) * 1e-9);
  if (!std::isfinite(hi)) return {lo};
  const double raw = hi / n - lo / n;  // (hi - lo) / n without overflowing
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  if (!(magnitude > 0) || !std::isfinite(magnitude)) return {lo, hi};
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  if (integer) step = std::max(1.0, std::round(step));
  const double first = std::ceil(lo / step) * step;
  std::vector<double> ticks;
  for (int k = 0; k <= 4 * n + 4; ++k) {  // about n of them; the bound holds whatever rounding does
    const double v = first + k * step;
    if (!(v <= hi + step * 1e-9)) break;
    ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  if (ticks.empty()) ticks.push_back(lo);
  return ticks;
}

void set_line_style(cairo_t* cr, ChartSeries::Line line) {
  static const double kDash[] = {6, 3};
  static const double kDot[] = {1.5, 2.5};
  if (line == ChartSeries::Line::kDashed) cairo_set_dash(cr, kDash, 2, 0);
  if (line == ChartSeries::Line::kDotted) cairo_set_dash(cr, kDot, 2, 0);
  if (line == ChartSeries::Line::kSolid) cairo_set_dash(cr, nullptr, 0, 0);
}

namespace {

// Values beyond this are drawn at it: no score, count or step of a run comes near, and within it the axis
// arithmetic has room (a span of 1e308 overflows a double).
constexpr double kChartLimit = 1e12;

double on_chart(double v) { return std::clamp(v, -kChartLimit, kChartLimit); }

std::string tick_label(double v) {
  char text[32];
  if (std::abs(v) >= 1e6 || (std::abs(v) < 1e-3 && v != 0))
    std::snprintf(text, sizeof text, "%.3g", v);
  else
    std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

void draw_chart(cairo_t* cr, double x, double y, double width, double height, const Chart& chart) {
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  bool any = false;
  for (const ChartSeries& s : chart.series)
    for (const auto& [vx, vy] : s.points) {
      if (!std::isfinite(vx) || !std::isfinite(vy)) continue;
      const double px = on_chart(vx), py = on_chart(vy);
      if (!any) x_lo = x_hi = px, y_lo = y_hi = py, any = true;
      x_lo = std::min(x_lo, px), x_hi = std::max(x_hi, px);
      y_lo = std::min(y_lo, py), y_hi = std::max(y_hi, py);
    }
  if (chart.reference_line && std::isfinite(chart.reference_line->first)) {
    const double ref = on_chart(chart.reference_line->first);
    y_lo = std::min(y_lo, ref), y_hi = std::max(y_hi, ref);
  }
  if (chart.y_min && std::isfinite(*chart.y_min)) y_lo = on_chart(*chart.y_min);
  if (chart.y_max && std::isfinite(*chart.y_max)) y_hi = on_chart(*chart.y_max);
  if (x_hi <= x_lo) x_hi = x_lo + 1;
  if (y_hi <= y_lo) y_hi = y_lo + 1;
  const std::vector<double> x_ticks = nice_ticks(x_lo, x_hi, 6, chart.integer_x);
  const std::vector<double> y_ticks = nice_ticks(y_lo, y_hi);
  x_lo = std::min(x_lo, x_ticks.front()), x_hi = std::max(x_hi, x_ticks.back());
  y_lo = std::min(y_lo, y_ticks.front()), y_hi = std::max(y_hi, y_ticks.back());

  // plot area, leaving room for the title, tick labels, axis labels and the legend on the right
  const double legend_width =
      std::any_of(chart.series.begin(), chart.series.end(), [](const ChartSeries& s) { return !s.label.empty(); }) ? 150
                                                                                                                   : 0;
  const double left = x + 62, right = x + width - 16 - legend_width, top = y + 34, bottom = y + height - 46;
  const auto px = [&](double v) { return left + (on_chart(v) - x_lo) / (x_hi - x_lo) * (right - left); };
  const auto py = [&](double v) { return bottom - (on_chart(v) - y_lo) / (y_hi - y_lo) * (bottom - top); };

  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  draw_text(cr, chart.title, (left + right) / 2, y + 20, 14, 0.5, true);
  draw_text(cr, chart.x_label, (left + right) / 2, y + height - 10, 12, 0.5);
  cairo_save(cr);
  cairo_translate(cr, x + 16, (top + bottom) / 2);
  cairo_rotate(cr, -M_PI / 2);
  draw_text(cr, chart.y_label, 0, 0, 12, 0.5);
  cairo_restore(cr);

  // grid and ticks
  cairo_set_line_width(cr, 1);
  for (double t : y_ticks) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, left, std::round(py(t)) + 0.5);
    cairo_line_to(cr, right, std::round(py(t)) + 0.5);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    draw_text(cr, tick_label(t), left - 6, py(t) + 4, 11, 1);
  }
  for (double t : x_ticks) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, std::round(px(t)) + 0.5, top);
    cairo_line_to(cr, std::round(px(t)) + 0.5, bottom);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    draw_text(cr, tick_label(t), px(t), bottom + 16, 11, 0.5);
  }
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  cairo_rectangle(cr, left + 0.5, top + 0.5, right - left, bottom - top);
  cairo_stroke(cr);

  cairo_save(cr);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_clip(cr);
  if (chart.reference_line && std::isfinite(chart.reference_line->first)) {
    const double ry = py(chart.reference_line->first);
    const double dash[] = {6, 4};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
    cairo_move_to(cr, left, ry);
    cairo_line_to(cr, right, ry);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    draw_text(cr, chart.reference_line->second, left + 6, ry - 5, 11);
  }
  for (const ChartSeries& s : chart.series) {
    if (s.points.empty()) continue;
    set_colour(cr, s.colour);
    cairo_set_line_width(cr, s.width);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    set_line_style(cr, s.line);
    bool started = false;
    double last_y = 0;
    for (const auto& [vx, vy] : s.points) {
      if (!std::isfinite(vx) || !std::isfinite(vy)) continue;
      if (!started) {
        cairo_move_to(cr, px(vx), py(vy));
        started = true;
      } else {
        if (s.steps) cairo_line_to(cr, px(vx), py(last_y));
        cairo_line_to(cr, px(vx), py(vy));
      }
      last_y = vy;
    }
    if (s.points.size() == 1 && started) {  // a lone point: a dot
      cairo_arc(cr, px(s.points[0].first), py(s.points[0].second), 2.5, 0, 2 * M_PI);
      cairo_fill(cr);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  cairo_restore(cr);

  // legend
  double ly = top + 8;
  for (const ChartSeries& s : chart.series) {
    if (s.label.empty()) continue;
    if (ly > bottom) break;
    set_colour(cr, s.colour);
    cairo_set_line_width(cr, std::max(1.5, s.width));
    set_line_style(cr, s.line);
    cairo_move_to(cr, right + 12, ly);
    cairo_line_to(cr, right + 36, ly);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    draw_text(cr, s.label, right + 42, ly + 4, 11);
    ly += 17;
  }
}

}  // namespace poet
