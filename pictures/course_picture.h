#pragma once
// Pictures of a course and of a walker's episode on it, drawn with cairo: ground, pit walls, stumps and stairs,
// the hull's path, and the walker's outline at regular intervals.

#include <string>

#include "common/plumbing/expected.h"
#include "pictures/canvas.h"
#include "simulation/rollout.h"
#include "simulation/walker/terrain.h"

namespace poet {

struct PictureOptions {
  double pixels_per_metre = 20.0;
  int snapshot_every = 50;  // draw the walker's outline every this many steps (0: never)
};

// The picture's bytes in the given format, or an error message.
Expected<std::string> render_course_picture(PictureFormat format, const Terrain& terrain, const RolloutResult& episode,
                                            const PictureOptions& options = {});

// Writes an SVG file (or PNG when the path ends in ".png"). Returns an error message, or empty on success.
std::string write_course_picture(const std::string& path, const Terrain& terrain, const RolloutResult& episode,
                                 const PictureOptions& options = {});

}  // namespace poet
