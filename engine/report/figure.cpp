#include "engine/report/figure.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "engine/report/raster_canvas.hpp"
#include "engine/report/svg_canvas.hpp"
#include "io/atomic_file.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::report {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string tick_label(double v, double step) {
  char buf[32];
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::fabs(v) < 1e-9 * step ? 0.0 : v);
  return buf;
}

}  // namespace

ImageFormat picture_format(const std::string& path, bool svg) {
  return svg || ends_with(path, ".svg") ? ImageFormat::kSvg : ImageFormat::kPng;
}

std::string picture_path(const std::string& path, bool svg) {
  return svg && ends_with(path, ".png") ? path.substr(0, path.size() - 4) + ".svg" : path;
}

std::string sibling_picture(const std::string& path, const std::string& suffix) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + suffix;
  return path.substr(0, dot) + suffix + path.substr(dot);
}

void write_picture(const std::string& path, ImageFormat format, int width, int height,
                   const std::function<void(Canvas&)>& draw) {
  std::string bytes;
  if (format == ImageFormat::kSvg) {
    SvgCanvas canvas(width, height);
    draw(canvas);
    bytes = canvas.document();
  } else {
    RasterCanvas canvas(width, height);
    draw(canvas);
    bytes = encode_png(width, height, canvas.rgb_bytes());
  }
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw InputError(path + ": cannot write the picture (disk full or not writable?)");
  });
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  if (!(hi > lo) || count < 1) return {lo};
  const double raw = (hi - lo) / count, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag, step = (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
  std::vector<double> ticks;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) ticks.push_back(v);
  return ticks;
}

void PlotArea::equal_aspect() {
  const double sx = (x1 - x0) / width, sy = (y1 - y0) / height;  // data units per pixel
  if (sx > sy) {
    const double mid = 0.5 * (y0 + y1), half = 0.5 * sx * height;
    y0 = mid - half, y1 = mid + half;
  } else {
    const double mid = 0.5 * (x0 + x1), half = 0.5 * sy * width;
    x0 = mid - half, x1 = mid + half;
  }
}

void PlotArea::draw_axes(Canvas& c, const std::string& xlabel, const std::string& ylabel) const {
  const Rgb grid = rgb(0xe4e4e4), ink = rgb(0x333333);
  const auto xt = nice_ticks(x0, x1, 8), yt = nice_ticks(y0, y1, 8);
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double v : xt) {
    c.line(px(v), top, px(v), top + height, {grid, 1.0});
    c.text(px(v), top + height + 16, tick_label(v, xstep), ink, Anchor::kMiddle);
  }
  for (double v : yt) {
    c.line(left, py(v), left + width, py(v), {grid, 1.0});
    c.text(left - 6, py(v) + 4, tick_label(v, ystep), ink, Anchor::kEnd);
  }
  c.outline_rect(left, top, width, height, {ink, 1.0});
  c.text(left + 0.5 * width, top + height + 36, xlabel, ink, Anchor::kMiddle);
  c.text(left - 46, top + 0.5 * height, ylabel, ink, Anchor::kMiddle, Face::kRegular, true);
}

}  // namespace trackassoc::report
