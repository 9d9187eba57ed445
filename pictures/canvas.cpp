#include "pictures/canvas.h"

#include <cairo-svg.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

namespace poet {

Rgb palette_colour(size_t index) {
  // Tableau 10: distinguishable on white and for common colour-vision deficiencies
  static constexpr std::array<Rgb, 10> kPalette = {{{0.122, 0.467, 0.706},
                                                    {1.000, 0.498, 0.055},
                                                    {0.173, 0.627, 0.173},
                                                    {0.839, 0.153, 0.157},
                                                    {0.580, 0.404, 0.741},
                                                    {0.549, 0.337, 0.294},
                                                    {0.890, 0.467, 0.761},
                                                    {0.498, 0.498, 0.498},
                                                    {0.737, 0.741, 0.133},
                                                    {0.090, 0.745, 0.812}}};
  return kPalette[index % kPalette.size()];
}

PictureFormat format_of(const std::string& path) {
  return path.size() > 4 && path.compare(path.size() - 4, 4, ".png") == 0 ? PictureFormat::kPng : PictureFormat::kSvg;
}

namespace {

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

Expected<std::string> render_picture(PictureFormat format, double width, double height,
                                     const std::function<void(cairo_t*)>& draw) {
  if (!(width >= 1 && height >= 1 && width <= 32768 && height <= 32768))
    return Unexpected{"picture size " + std::to_string(width) + " × " + std::to_string(height) + " out of range"};
  std::string bytes;
  const bool png = format == PictureFormat::kPng;
  using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
  SurfacePtr surface(
      png ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(width), static_cast<int>(height))
          : cairo_svg_surface_create_for_stream(append_bytes, &bytes, width, height),
      &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    return Unexpected{std::string("cannot make a picture: ") +
                      cairo_status_to_string(cairo_surface_status(surface.get()))};
  {
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> ctx(cairo_create(surface.get()), &cairo_destroy);
    cairo_set_source_rgb(ctx.get(), 1, 1, 1);
    cairo_paint(ctx.get());
    draw(ctx.get());
  }
  cairo_surface_flush(surface.get());
  if (png && cairo_surface_write_to_png_stream(surface.get(), append_bytes, &bytes) != CAIRO_STATUS_SUCCESS)
    return Unexpected{"cannot encode the PNG"};
  cairo_surface_finish(surface.get());
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    return Unexpected{std::string("cannot draw the picture: ") +
                      cairo_status_to_string(cairo_surface_status(surface.get()))};
  return bytes;
}

std::string write_bytes(const std::string& path, const std::string& bytes) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return "cannot write " + path + ": " + std::strerror(errno);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      return "cannot write " + path + ": " + std::strerror(errno);
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    return "cannot write " + path + ": " + reason;
  }
  return {};
}

std::string write_picture(const std::string& path, double width, double height,
                          const std::function<void(cairo_t*)>& draw) {
  Expected<std::string> bytes = render_picture(format_of(path), width, height, draw);
  if (!bytes) return "cannot draw " + path + ": " + bytes.error();
  return write_bytes(path, *bytes);
}

void draw_text(cairo_t* cr, const std::string& text, double x, double y, double size, double anchor_x, bool bold) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  cairo_move_to(cr, x - anchor_x * extents.x_advance, y);
  cairo_show_text(cr, text.c_str());
}

}  // namespace poet
