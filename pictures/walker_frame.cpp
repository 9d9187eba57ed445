#include "pictures/walker_frame.h"

#include <cairo.h>

#include <memory>
#include <string>

#include "pictures/course_drawing.h"

namespace poet {

std::optional<std::string> frame_options_error(const FrameOptions& options) {
  for (const auto& [name, value] : {std::pair{"width", options.width}, std::pair{"height", options.height}})
    if (value < kMinFramePixels || value > kMaxFramePixels)
      return std::string(name) + " must be in [" + std::to_string(kMinFramePixels) + ", " +
             std::to_string(kMaxFramePixels) + "] pixels, got " + std::to_string(value);
  if (!(options.pixels_per_metre > 0 && options.pixels_per_metre <= 1000))
    return "pixels_per_metre must be in (0, 1000], got " + std::to_string(options.pixels_per_metre);
  return std::nullopt;
}

Expected<FrameImage> render_walker_frame(const Terrain& terrain, const WalkerPose& pose, const FrameOptions& options) {
  if (auto error = frame_options_error(options)) return Unexpected{*error};
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, options.width, options.height), &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    return Unexpected{std::string("cairo: ") + cairo_status_to_string(cairo_surface_status(surface.get()))};
  {
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), &cairo_destroy);
    const Frame f = follow_camera(terrain, pose, options.width, options.height, options.pixels_per_metre);
    draw_course(cr.get(), f, terrain, options.height);
    draw_walker(cr.get(), f, pose, 1.0);
  }
  cairo_surface_flush(surface.get());
  FrameImage image{options.width, options.height, {}};
  image.rgb.resize(static_cast<size_t>(options.width) * static_cast<size_t>(options.height) * 3);
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  size_t k = 0;
  for (int y = 0; y < options.height; ++y) {
    const auto* pixels = reinterpret_cast<const uint32_t*>(data + static_cast<ptrdiff_t>(y) * stride);
    for (int x = 0; x < options.width; ++x) {  // RGB24: 0x00RRGGBB in a native-endian word
      image.rgb[k++] = static_cast<uint8_t>(pixels[x] >> 16);
      image.rgb[k++] = static_cast<uint8_t>(pixels[x] >> 8);
      image.rgb[k++] = static_cast<uint8_t>(pixels[x]);
    }
  }
  return image;
}

}  // namespace poet
