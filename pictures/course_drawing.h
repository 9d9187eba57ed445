#pragma once
// Drawing a course and the walker with cairo in world coordinates: the pieces every picture of an episode shares
// (the whole-course picture, the filmstrip, the animated GIF).

#include <cairo.h>

#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_env.h"

namespace poet {

// World metres → canvas units: x from x_min rightwards, y from y_max downwards, `scale` units per metre.
struct Frame {
  double x_min = 0, y_max = 0, scale = 1;
  double px(double x) const { return (x - x_min) * scale; }
  double py(double y) const { return (y_max - y) * scale; }
};

// The camera of a panel or frame following the walker: the window centred on the hull, the ground under it a
// quarter of the height from the bottom (so courses that climb stay in view), `scale` units per metre.
Frame follow_camera(const Terrain& terrain, const WalkerPose& pose, double width, double height, double scale);

// Sky, the ground filled down to canvas height `bottom`, obstacles (pit walls grey, stumps brown, stairs
// blue-grey) and the finish line.
void draw_course(cairo_t* cr, const Frame& f, const Terrain& terrain, double bottom);

// The walker's hull and legs at a pose (far leg first), with opacity alpha.
void draw_walker(cairo_t* cr, const Frame& f, const WalkerPose& pose, double alpha);

}  // namespace poet
