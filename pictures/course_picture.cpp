#include "pictures/course_picture.h"

#include <algorithm>

#include "pictures/canvas.h"
#include "pictures/course_drawing.h"
#include "simulation/walker/walker_constants.h"

namespace poet {

using namespace walker;

Expected<std::string> render_course_picture(PictureFormat format, const Terrain& terrain, const RolloutResult& episode,
                                            const PictureOptions& options) {
  if (!(options.pixels_per_metre > 0) || options.pixels_per_metre > 200)
    return Unexpected{"pixels_per_metre must be in (0, 200]"};
  const auto& ground = terrain.ground();
  double y_min = ground.front().y, y_max = ground.front().y;
  for (const Point& p : ground) y_min = std::min(y_min, p.y), y_max = std::max(y_max, p.y);
  for (const TerrainBox& b : terrain.boxes()) y_min = std::min(y_min, b.y0), y_max = std::max(y_max, b.y1);
  for (const WalkerPose& p : episode.trajectory) y_max = std::max(y_max, double(p[0].y));
  const Frame f{ground.front().x - 1.0, y_max + 2.5, options.pixels_per_metre};
  const double width = (ground.back().x + 1.0 - f.x_min) * f.scale;
  const double height = (f.y_max - (y_min - 1.0)) * f.scale;

  return render_picture(format, width, height, [&](cairo_t* cr) {
    draw_course(cr, f, terrain, height);
    const auto& traj = episode.trajectory;
    if (options.snapshot_every > 0)
      for (size_t i = 0; i < traj.size(); i += static_cast<size_t>(options.snapshot_every))
        draw_walker(cr, f, traj[i], 0.35);
    if (!traj.empty()) {
      cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
      cairo_set_line_width(cr, 1.5);
      cairo_move_to(cr, f.px(traj[0][0].x), f.py(traj[0][0].y));
      for (const WalkerPose& p : traj) cairo_line_to(cr, f.px(p[0].x), f.py(p[0].y));
      cairo_stroke(cr);
      draw_walker(cr, f, traj.back(), 1.0);
    }
  });
}

std::string write_course_picture(const std::string& path, const Terrain& terrain, const RolloutResult& episode,
                                 const PictureOptions& options) {
  Expected<std::string> bytes = render_course_picture(format_of(path), terrain, episode, options);
  if (!bytes) return "cannot draw " + path + ": " + bytes.error();
  return write_bytes(path, *bytes);
}

}  // namespace poet
