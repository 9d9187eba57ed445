#pragma once
// One picture file drawn with cairo: PNG when the path ends in ".png", SVG otherwise. The draw callback paints
// on a width × height canvas (pixels for PNG, points for SVG).

#include <cairo.h>

#include <functional>
#include <string>

#include "common/plumbing/expected.h"

namespace poet {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

// A colour per series: a qualitative palette of 10, repeated.
Rgb palette_colour(size_t index);

inline void set_colour(cairo_t* cr, Rgb c, double alpha = 1.0) { cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha); }

enum class PictureFormat { kPng, kSvg };

// The format a path asks for: PNG for ".png", SVG otherwise.
PictureFormat format_of(const std::string& path);

// The picture's bytes, or an error message.
Expected<std::string> render_picture(PictureFormat format, double width, double height,
                                     const std::function<void(cairo_t*)>& draw);

// render_picture in the path's format, written to path. Returns an error message naming the file, or empty.
std::string write_picture(const std::string& path, double width, double height,
                          const std::function<void(cairo_t*)>& draw);

// Writes bytes to path (a temporary file beside it, then a rename, so a reader never sees half a picture).
// Returns an error message naming the file, or empty.
std::string write_bytes(const std::string& path, const std::string& bytes);

// Text at (x, y): anchor_x 0 left, 0.5 centre, 1 right; y is the baseline.
void draw_text(cairo_t* cr, const std::string& text, double x, double y, double size, double anchor_x = 0,
               bool bold = false);

}  // namespace poet
