#pragma once
// One frame of the walker on its course as pixels, for programs that show it themselves (the Python module's
// render()): the camera follows the hull as in the animated GIF.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_env.h"

namespace poet {

inline constexpr int kMinFramePixels = 16, kMaxFramePixels = 4096;  // a frame's width and height

struct FrameOptions {
  int width = 600, height = 400;  // pixels, each in [kMinFramePixels, kMaxFramePixels]
  double pixels_per_metre = 30;   // in (0, 1000]
};

// Row-major 8-bit RGB, width × height × 3 bytes.
struct FrameImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

// Why the options cannot be drawn (the option out of range), or nothing when they can.
std::optional<std::string> frame_options_error(const FrameOptions& options);

// The frame, or an error naming the option out of range.
Expected<FrameImage> render_walker_frame(const Terrain& terrain, const WalkerPose& pose,
                                         const FrameOptions& options = {});

}  // namespace poet
