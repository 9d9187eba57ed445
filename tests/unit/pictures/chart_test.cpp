#include "pictures/chart.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace poet {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(NiceTicks, RoundStepsCoverTheRange) {
  const std::vector<double> ticks = nice_ticks(0, 230);
  ASSERT_FALSE(ticks.empty());
  EXPECT_EQ(ticks.front(), 0);
  EXPECT_GE(ticks.back(), 200);
  EXPECT_EQ(ticks[1] - ticks[0], 50);
  EXPECT_EQ(nice_ticks(0, 3, 6, true), (std::vector<double>{0, 1, 2, 3}));
}

// Bounds a run's files could hold (finite scores of ±1e308, a constant series near 1e300) or worse: a few finite
// ticks every time, never none (the chart indexes the first and last), never an endless list.
TEST(NiceTicks, AnyBoundsGiveAFewFiniteTicks) {
  const std::pair<double, double> bounds[] = {{-1e308, 1e308}, {1e300, 1e300},   {1.7e308, 1.7e308}, {5, 5},
                                              {0, 1e-320},     {-kInf, kInf},    {NAN, NAN},         {3, -3},
                                              {0, kInf},       {-1e308, -1e308}, {1e-300, 2e-300}};
  for (const auto& [lo, hi] : bounds) {
    for (const bool integer : {false, true}) {
      const std::vector<double> ticks = nice_ticks(lo, hi, 6, integer);
      ASSERT_FALSE(ticks.empty()) << lo << " " << hi;
      EXPECT_LE(ticks.size(), 28u) << lo << " " << hi;
      for (double t : ticks) EXPECT_TRUE(std::isfinite(t)) << lo << " " << hi;
    }
  }
}

TEST(DrawChart, ExtremeValuesAreDrawnWithoutFailing) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 400, 300);
  cairo_t* cr = cairo_create(surface);
  Chart chart;
  chart.series.push_back({"scores", {{0, 1e308}, {1, -1e308}, {2, NAN}, {kInf, 5}}, Rgb{0, 0, 1}});
  chart.series.push_back({"", {{1e300, 1e300}}, Rgb{1, 0, 0}});  // a lone point
  chart.reference_line = {{1e308, "solved"}};
  chart.y_min = -kInf;
  draw_chart(cr, 0, 0, 400, 300, chart);
  EXPECT_EQ(cairo_status(cr), CAIRO_STATUS_SUCCESS);
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
}

}  // namespace
}  // namespace poet
