#pragma once
// Line charts drawn with cairo: axes with round-number ticks, one polyline per series, an optional horizontal
// reference line and a legend. Enough for score curves and counts over iterations; no plotting runtime needed.

#include <cairo.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pictures/canvas.h"

namespace poet {

struct ChartSeries {
  std::string label;  // empty: not in the legend
  std::vector<std::pair<double, double>> points;
  Rgb colour;
  enum class Line { kSolid, kDashed, kDotted } line = Line::kSolid;
  bool steps = false;  // a step function (counts): horizontal, then vertical
  double width = 1.6;
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<ChartSeries> series;
  std::optional<std::pair<double, std::string>> reference_line;  // y value and its label
  std::optional<double> y_min, y_max;                            // fixed bounds; otherwise from the data
  bool integer_x = false;                                        // x ticks on whole numbers (iterations)
};

// Draws the chart in the rectangle (x, y, width, height) of cr.
void draw_chart(cairo_t* cr, double x, double y, double width, double height, const Chart& chart);

// Round tick values covering [lo, hi]: steps of 1, 2 or 5 × 10^k, about `target` of them; with integer, no step
// below 1.
std::vector<double> nice_ticks(double lo, double hi, int target = 6, bool integer = false);

// Sets cr's dash pattern for a series' line style.
void set_line_style(cairo_t* cr, ChartSeries::Line line);

}  // namespace poet
