// Pictures as files: PNG (the raster canvas) by default, SVG on request, written atomically; and
// the axes shared by the figures (a plot area mapping data to pixels, with round tick values).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "engine/report/canvas.hpp"

namespace trackassoc::report {

enum class ImageFormat { kPng, kSvg };

// SVG when `svg` is set or `path` ends in ".svg"; PNG otherwise.
ImageFormat picture_format(const std::string& path, bool svg);
// `path` with its ".png" turned into ".svg" when `svg` (the --svg flag on a default name).
std::string picture_path(const std::string& path, bool svg);
// A picture beside `path`: "out/run.png" with "-summary" gives "out/run-summary.png".
std::string sibling_picture(const std::string& path, const std::string& suffix);

// Draws on a width × height canvas of `format` and writes it to `path` atomically
// (io/atomic_file.hpp). Throws InputError when the file cannot be written.
void write_picture(const std::string& path, ImageFormat format, int width, int height,
                   const std::function<void(Canvas&)>& draw);

// Round tick values (1, 2 or 5 × 10^k apart) covering [lo, hi], about `count` of them.
std::vector<double> nice_ticks(double lo, double hi, int count);

// A rectangle of the canvas showing the data box [x0, x1] × [y0, y1] (y up).
struct PlotArea {
  double left = 0, top = 0, width = 1, height = 1;  // [px]
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;            // data
  double px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }
  // Widens the shorter data range so one unit is as long on both axes (a map).
  void equal_aspect();
  // Frame, grid lines and tick labels, and the axis labels.
  void draw_axes(Canvas& canvas, const std::string& xlabel, const std::string& ylabel) const;
};

}  // namespace trackassoc::report
