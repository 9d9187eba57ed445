#include "pictures/course_stack.h"

#include <algorithm>

#include "pictures/course_drawing.h"

namespace poet {

Expected<std::string> render_course_stack(PictureFormat format, const std::vector<LabelledCourse>& courses,
                                          double width) {
  if (courses.empty()) return Unexpected{std::string("no course to draw")};
  if (courses.size() > kMaxStackedCourses)
    return Unexpected{std::to_string(courses.size()) + " courses; at most " + std::to_string(kMaxStackedCourses)};
  if (!(width >= 200 && width <= 4000)) return Unexpected{std::string("width must be in [200, 4000]")};
  double x_max = 0, relief = 1.0;  // metres; at least 1 m of height per band
  std::vector<double> lowest;      // each course's lowest point: the bottom of its band
  for (const LabelledCourse& c : courses) {
    const auto& g = c.terrain.ground();
    double lo = g.front().y, hi = g.front().y;
    for (const Point& p : g) lo = std::min(lo, p.y), hi = std::max(hi, p.y);
    for (const TerrainBox& b : c.terrain.boxes()) lo = std::min(lo, b.y0), hi = std::max(hi, b.y1);
    lowest.push_back(lo);
    relief = std::max(relief, hi - lo);
    x_max = std::max(x_max, g.back().x);
  }
  // true proportions: one scale for both axes, the course across the width unless a band would pass 600 units
  const double scale = std::min(width / (x_max + 2.0), 600.0 / (relief + 2.0));
  const double label_height = 18, band_height = (relief + 2.0) * scale;
  const double height = courses.size() * (band_height + label_height);

  return render_picture(format, width, height, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (size_t i = 0; i < courses.size(); ++i) {
      const double top = i * (band_height + label_height);
      cairo_save(cr);
      cairo_rectangle(cr, 0, top + label_height, width, band_height);
      cairo_clip(cr);
      cairo_translate(cr, 0, top + label_height);
      const Frame f{-1.0, lowest[i] + relief + 1.0, scale};
      draw_course(cr, f, courses[i].terrain, band_height);
      cairo_restore(cr);
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      draw_text(cr, courses[i].label, 6, top + label_height - 5, 12);
    }
  });
}

}  // namespace poet
