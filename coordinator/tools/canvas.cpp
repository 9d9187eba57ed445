#include "canvas.h"

#include <cairo-svg.h>

#include <array>
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

std::string write_picture(const std::string& path, double width, double height,
                          const std::function<void(cairo_t*)>& draw) {
  if (!(width >= 1 && height >= 1 && width <= 32768 && height <= 32768))
    return "cannot draw " + path + ": size " + std::to_string(width) + " × " + std::to_string(height) + " out of range";
  const bool png = path.size() > 4 && path.compare(path.size() - 4, 4, ".png") == 0;
  using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
  SurfacePtr surface(
      png ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(width), static_cast<int>(height))
          : cairo_svg_surface_create(path.c_str(), width, height),
      &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    return "cannot create " + path + ": " + cairo_status_to_string(cairo_surface_status(surface.get()));
  {
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> ctx(cairo_create(surface.get()), &cairo_destroy);
    cairo_set_source_rgb(ctx.get(), 1, 1, 1);
    cairo_paint(ctx.get());
    draw(ctx.get());
  }
  cairo_surface_flush(surface.get());
  if (png && cairo_surface_write_to_png(surface.get(), path.c_str()) != CAIRO_STATUS_SUCCESS)
    return "cannot write " + path;
  cairo_surface_finish(surface.get());
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    return "cannot write " + path + ": " + cairo_status_to_string(cairo_surface_status(surface.get()));
  return {};
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
