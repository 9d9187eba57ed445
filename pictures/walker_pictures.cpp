#include "pictures/walker_pictures.h"

#include <gif_lib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "pictures/course_drawing.h"

namespace poet {
namespace {

void draw_hull_path(cairo_t* cr, const Frame& f, const RolloutResult& episode, size_t until) {
  cairo_set_source_rgba(cr, 0.8, 0.1, 0.1, 0.7);
  cairo_set_line_width(cr, 1.5);
  const auto& t = episode.trajectory;
  cairo_move_to(cr, f.px(t[0][0].x), f.py(t[0][0].y));
  for (size_t i = 1; i <= until && i < t.size(); ++i) cairo_line_to(cr, f.px(t[i][0].x), f.py(t[i][0].y));
  cairo_stroke(cr);
}

// A 6 × 7 × 6 colour cube (252 entries): every frame uses this one palette, so frames need no local colour maps.
constexpr int kRed = 6, kGreen = 7, kBlue = 6;

uint8_t palette_index(uint32_t rgb) {
  const int r = static_cast<int>((rgb >> 16) & 0xff), g = static_cast<int>((rgb >> 8) & 0xff),
            b = static_cast<int>(rgb & 0xff);
  const int ri = (r * (kRed - 1) + 127) / 255, gi = (g * (kGreen - 1) + 127) / 255, bi = (b * (kBlue - 1) + 127) / 255;
  return static_cast<uint8_t>((ri * kGreen + gi) * kBlue + bi);
}

int append_gif_bytes(GifFileType* gif, const GifByteType* data, int length) {
  static_cast<std::string*>(gif->UserData)->append(reinterpret_cast<const char*>(data), static_cast<size_t>(length));
  return length;
}

}  // namespace

Expected<std::string> render_filmstrip(PictureFormat format, const Terrain& terrain, const RolloutResult& episode,
                                       const FilmstripOptions& options) {
  if (episode.trajectory.empty()) return Unexpected{"the episode has no recorded trajectory"};
  if (options.panels < 1 || options.panels > 64) return Unexpected{"panels must be in [1, 64]"};
  if (!(options.window_metres >= 2 && options.window_metres <= 200)) return Unexpected{"window must be in [2, 200] m"};
  if (!(options.pixels_per_metre > 0 && options.pixels_per_metre <= 200))
    return Unexpected{"pixels_per_metre must be in (0, 200]"};
  const double width = options.window_metres * options.pixels_per_metre;
  const double panel_height = std::round(width * 0.3);
  const double label = 18;
  const size_t last = episode.trajectory.size() - 1;
  return render_picture(format, width, options.panels * (panel_height + label), [&](cairo_t* cr) {
    for (int k = 0; k < options.panels; ++k) {
      const size_t step =
          options.panels == 1 ? last : last * static_cast<size_t>(k) / static_cast<size_t>(options.panels - 1);
      const WalkerPose& pose = episode.trajectory[step];
      const double top = k * (panel_height + label);
      cairo_save(cr);
      cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
      char text[96];
      std::snprintf(text, sizeof text, "step %zu   x = %.1f m", step, static_cast<double>(pose[0].x));
      draw_text(cr, text, 6, top + 13, 11);
      cairo_rectangle(cr, 0, top + label, width, panel_height);
      cairo_clip(cr);
      cairo_translate(cr, 0, top + label);
      const Frame f = follow_camera(terrain, pose, width, panel_height, options.pixels_per_metre);
      draw_course(cr, f, terrain, panel_height);
      draw_hull_path(cr, f, episode, step);
      draw_walker(cr, f, pose, 1.0);
      cairo_restore(cr);
    }
  });
}

Expected<std::string> render_walk_gif(const Terrain& terrain, const RolloutResult& episode, const GifOptions& options) {
  if (episode.trajectory.empty()) return Unexpected{"the episode has no recorded trajectory"};
  if (options.every < 1 || options.every > 1000) return Unexpected{"every must be in [1, 1000] steps"};
  if (options.width < 16 || options.width > 2000 || options.height < 16 || options.height > 2000)
    return Unexpected{"frame size must be in [16, 2000] pixels"};
  if (options.delay_centiseconds < 1 || options.delay_centiseconds > 1000)
    return Unexpected{"delay must be in [1, 1000] centiseconds"};

  std::vector<GifColorType> colours(256, GifColorType{0, 0, 0});
  for (int r = 0; r < kRed; ++r)
    for (int g = 0; g < kGreen; ++g)
      for (int b = 0; b < kBlue; ++b)
        colours[static_cast<size_t>((r * kGreen + g) * kBlue + b)] = {static_cast<GifByteType>(r * 255 / (kRed - 1)),
                                                                      static_cast<GifByteType>(g * 255 / (kGreen - 1)),
                                                                      static_cast<GifByteType>(b * 255 / (kBlue - 1))};
  std::string bytes;
  int error = 0;
  GifFileType* gif = EGifOpen(&bytes, append_gif_bytes, &error);
  if (!gif) return Unexpected{std::string("giflib: ") + GifErrorString(error)};
  const auto fail = [&](const char* what) {
    const std::string message = std::string("giflib: ") + what + ": " + GifErrorString(gif->Error);
    EGifCloseFile(gif, &error);
    return Unexpected{message};
  };
  EGifSetGifVersion(gif, true);  // GIF89a: the frame delays and the loop need its extensions
  ColorMapObject* map = GifMakeMapObject(256, colours.data());
  const int screen = EGifPutScreenDesc(gif, options.width, options.height, 8, 0, map);
  GifFreeMapObject(map);
  if (screen != GIF_OK) return fail("screen");
  // loop for ever (the NETSCAPE2.0 application extension)
  const GifByteType loop[3] = {1, 0, 0};
  if (EGifPutExtensionLeader(gif, APPLICATION_EXT_FUNC_CODE) != GIF_OK ||
      EGifPutExtensionBlock(gif, 11, "NETSCAPE2.0") != GIF_OK || EGifPutExtensionBlock(gif, 3, loop) != GIF_OK ||
      EGifPutExtensionTrailer(gif) != GIF_OK)
    return fail("loop extension");

  using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, options.width, options.height),
                     &cairo_surface_destroy);
  std::vector<GifPixelType> row(static_cast<size_t>(options.width));
  const size_t n = episode.trajectory.size();
  for (size_t step = 0; step < n; step += static_cast<size_t>(options.every)) {
    const bool last_frame = step + static_cast<size_t>(options.every) >= n;
    const size_t shown = last_frame ? n - 1 : step;
    {
      std::unique_ptr<cairo_t, decltype(&cairo_destroy)> ctx(cairo_create(surface.get()), &cairo_destroy);
      cairo_t* cr = ctx.get();
      const WalkerPose& pose = episode.trajectory[shown];
      const Frame f = follow_camera(terrain, pose, options.width, options.height, options.pixels_per_metre);
      draw_course(cr, f, terrain, options.height);
      draw_hull_path(cr, f, episode, shown);
      draw_walker(cr, f, pose, 1.0);
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      char text[64];
      std::snprintf(text, sizeof text, "step %zu", shown);
      draw_text(cr, text, 6, 14, 11);
    }
    cairo_surface_flush(surface.get());
    GraphicsControlBlock control{DISPOSAL_UNSPECIFIED, false, last_frame ? 200 : options.delay_centiseconds,
                                 NO_TRANSPARENT_COLOR};
    GifByteType extension[4];
    EGifGCBToExtension(&control, extension);
    if (EGifPutExtension(gif, GRAPHICS_EXT_FUNC_CODE, 4, extension) != GIF_OK) return fail("frame delay");
    if (EGifPutImageDesc(gif, 0, 0, options.width, options.height, false, nullptr) != GIF_OK) return fail("frame");
    const unsigned char* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    for (int y = 0; y < options.height; ++y) {
      const auto* pixels = reinterpret_cast<const uint32_t*>(data + static_cast<ptrdiff_t>(y) * stride);
      for (int x = 0; x < options.width; ++x) row[static_cast<size_t>(x)] = palette_index(pixels[x]);
      if (EGifPutLine(gif, row.data(), options.width) != GIF_OK) return fail("pixels");
    }
    if (last_frame) break;
  }
  if (EGifCloseFile(gif, &error) != GIF_OK) return Unexpected{std::string("giflib: ") + GifErrorString(error)};
  return bytes;
}

}  // namespace poet
