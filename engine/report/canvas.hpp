// A drawing surface for the pictures of the CLI (the map of an association, the summary chart of
// `trackassoc run`): a few primitives in pixel coordinates (origin top left, y down), drawn either
// into a raster (engine/report/raster_canvas.hpp, written as PNG) or as SVG elements
// (engine/report/svg_canvas.hpp), so one drawing routine serves both formats.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace trackassoc::report {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};
// 0xRRGGBB -> Rgb.
constexpr Rgb rgb(uint32_t hex) {
  return {static_cast<uint8_t>(hex >> 16), static_cast<uint8_t>(hex >> 8), static_cast<uint8_t>(hex)};
}

struct Point {
  double x = 0.0, y = 0.0;
};

struct Stroke {
  Rgb colour;
  double width = 1.0;        // [px]
  std::vector<double> dash;  // on, off, on, off ... [px]; empty = solid
  double opacity = 1.0;
  Stroke(Rgb c, double w = 1.0, std::vector<double> d = {}, double o = 1.0)
      : colour(c), width(w), dash(std::move(d)), opacity(o) {}
};

enum class Anchor { kStart, kMiddle, kEnd };
enum class Face { kRegular, kBold };  // engine/report/font.hpp: 13 px labels, 16 px bold titles
enum class Marker { kCircle, kSquare, kTriangle, kDiamond, kTriangleDown };

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height) {}
  virtual ~Canvas() = default;
  int width() const { return width_; }
  int height() const { return height_; }

  virtual void fill_rect(double x, double y, double w, double h, Rgb colour, double opacity = 1.0) = 0;
  // An open polyline; dashes run along its whole length.
  virtual void polyline(const std::vector<Point>& points, const Stroke& stroke) = 0;
  // A marker of `size` px across centred on (x, y), filled, with a 1 px edge.
  virtual void marker(double x, double y, Marker shape, double size, Rgb fill, Rgb edge) = 0;
  // Text on the baseline y; `vertical` turns it 90° counter-clockwise (reading upwards), the
  // anchor then running along the text as before.
  virtual void text(double x, double y, const std::string& text, Rgb colour, Anchor anchor = Anchor::kStart,
                    Face face = Face::kRegular, bool vertical = false) = 0;

  void line(double x0, double y0, double x1, double y1, const Stroke& stroke) {
    polyline({{x0, y0}, {x1, y1}}, stroke);
  }
  void outline_rect(double x, double y, double w, double h, const Stroke& stroke) {
    polyline({{x, y}, {x + w, y}, {x + w, y + h}, {x, y + h}, {x, y}}, stroke);
  }
  // The width of `text` in pixels, the same in both formats (the SVG names the same font).
  static int text_width(const std::string& text, Face face = Face::kRegular);

 private:
  int width_, height_;
};

// The outline of a marker other than the circle, `size` px across, centred on (x, y).
std::vector<Point> marker_outline(Marker shape, double x, double y, double size);

// The pieces of a polyline that a dash pattern draws (the whole line when `dash` is empty).
std::vector<std::vector<Point>> dash_polyline(const std::vector<Point>& points,
                                              const std::vector<double>& dash);

}  // namespace trackassoc::report
