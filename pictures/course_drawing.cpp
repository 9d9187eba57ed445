#include "pictures/course_drawing.h"

#include <cmath>

#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

using namespace walker;

void polygon(cairo_t* cr, const Frame& f, const double (*pts)[2], int n) {
  cairo_move_to(cr, f.px(pts[0][0]), f.py(pts[0][1]));
  for (int i = 1; i < n; ++i) cairo_line_to(cr, f.px(pts[i][0]), f.py(pts[i][1]));
  cairo_close_path(cr);
}

// A body's box or polygon (local coordinates, metres) placed at a pose.
void body_outline(cairo_t* cr, const Frame& f, const BodyPose& pose, const double (*local)[2], int n) {
  double world[8][2];
  const double c = std::cos(pose.angle), s = std::sin(pose.angle);
  for (int i = 0; i < n; ++i) {
    world[i][0] = pose.x + c * local[i][0] - s * local[i][1];
    world[i][1] = pose.y + s * local[i][0] + c * local[i][1];
  }
  polygon(cr, f, world, n);
}

}  // namespace

void draw_walker(cairo_t* cr, const Frame& f, const WalkerPose& pose, double alpha) {
  double hull[5][2];
  for (int i = 0; i < 5; ++i) hull[i][0] = kHullPoly[i][0] / kScale, hull[i][1] = kHullPoly[i][1] / kScale;
  const double uw = kLegW / 2, lw = kLowerLegWidthFactor * kLegW / 2, h = kLegH / 2;
  const double upper[4][2] = {{-uw, -h}, {uw, -h}, {uw, h}, {-uw, h}};
  const double lower[4][2] = {{-lw, -h}, {lw, -h}, {lw, h}, {-lw, h}};
  // far leg first so the near leg and the hull are drawn over it
  for (int leg : {1, 0}) {
    const double shade = leg == 0 ? 0.55 : 0.35;
    cairo_set_source_rgba(cr, shade, 0.25, 0.45, alpha);
    body_outline(cr, f, pose[1 + 2 * leg], upper, 4);
    cairo_fill(cr);
    body_outline(cr, f, pose[2 + 2 * leg], lower, 4);
    cairo_fill(cr);
  }
  cairo_set_source_rgba(cr, 0.5, 0.4, 0.9, alpha);
  body_outline(cr, f, pose[0], hull, 5);
  cairo_fill_preserve(cr);
  cairo_set_source_rgba(cr, 0.3, 0.3, 0.5, alpha);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

Frame follow_camera(const Terrain& terrain, const WalkerPose& pose, double width, double height, double scale) {
  const double x_min = pose[0].x - width / scale / 2;
  double ground = terrain.ground().front().y;
  for (const Point& p : terrain.ground())
    if (p.x <= pose[0].x) ground = p.y;
  return Frame{x_min, ground + (height * 0.75) / scale, scale};
}

void draw_course(cairo_t* cr, const Frame& f, const Terrain& terrain, double bottom) {
  const auto& ground = terrain.ground();
  // sky
  cairo_set_source_rgb(cr, 0.9, 0.9, 1.0);
  cairo_paint(cr);
  // ground: filled down to the bottom of the picture, as the reference renders it
  cairo_move_to(cr, f.px(ground.front().x), bottom);
  for (const Point& p : ground) cairo_line_to(cr, f.px(p.x), f.py(p.y));
  cairo_line_to(cr, f.px(ground.back().x), bottom);
  cairo_close_path(cr);
  cairo_set_source_rgb(cr, 0.4, 0.6, 0.3);
  cairo_fill(cr);
  // obstacles: pit walls grey, stumps brown, stairs blue-grey
  for (const TerrainBox& b : terrain.boxes()) {
    const double r = b.kind == ObstacleKind::kStump ? 0.55 : b.kind == ObstacleKind::kStair ? 0.45 : 0.6;
    const double g = b.kind == ObstacleKind::kStump ? 0.35 : b.kind == ObstacleKind::kStair ? 0.5 : 0.6;
    const double bl = b.kind == ObstacleKind::kStump ? 0.2 : b.kind == ObstacleKind::kStair ? 0.6 : 0.6;
    cairo_rectangle(cr, f.px(b.x0), f.py(b.y1), (b.x1 - b.x0) * f.scale, (b.y1 - b.y0) * f.scale);
    cairo_set_source_rgb(cr, r, g, bl);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_set_line_width(cr, 0.8);
    cairo_stroke(cr);
  }
  // finish line
  cairo_set_source_rgb(cr, 0.9, 0.2, 0.0);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, f.px(kFinishX), f.py(kTerrainHeight - 1.0));
  cairo_line_to(cr, f.px(kFinishX), 0);
  cairo_stroke(cr);
}

}  // namespace poet
