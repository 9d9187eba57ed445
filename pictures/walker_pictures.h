#pragma once
// Pictures of one episode for people to look at: a filmstrip (panels following the walker at evenly spaced
// moments, stacked top to bottom; PNG or SVG) and an animated GIF (giflib) of the walker crossing its course.
// Both take an episode recorded with its trajectory.

#include <string>

#include "common/plumbing/expected.h"
#include "pictures/canvas.h"
#include "simulation/rollout.h"
#include "simulation/walker/terrain.h"

namespace poet {

struct FilmstripOptions {
  int panels = 8;
  double window_metres = 16;  // the width of the course each panel shows, centred on the hull
  double pixels_per_metre = 40;
};

struct GifOptions {
  int every = 4;               // a frame every this many steps (the simulation runs 50 steps per second)
  int delay_centiseconds = 8;  // between frames: 4 steps at 8 cs plays at half the simulation's speed
  int width = 560, height = 220;
  double pixels_per_metre = 28;
};

// The filmstrip's bytes in the given format (canvas.h), or an error (no trajectory, options out of range).
Expected<std::string> render_filmstrip(PictureFormat format, const Terrain& terrain, const RolloutResult& episode,
                                       const FilmstripOptions& options = {});

// The animated GIF's bytes (looping), or an error.
Expected<std::string> render_walk_gif(const Terrain& terrain, const RolloutResult& episode,
                                      const GifOptions& options = {});

}  // namespace poet
