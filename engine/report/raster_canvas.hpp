// A Canvas drawn into an 8-bit RGB raster with antialiasing: lines and markers by their exact
// coverage of each pixel (distance to the segment, 4 × 4 samples for polygons), text by the
// coverage of the built-in font (engine/report/font.hpp). encode_png writes the raster.
#pragma once

#include <string>
#include <vector>

#include "engine/report/canvas.hpp"

namespace trackassoc::report {

class RasterCanvas final : public Canvas {
 public:
  RasterCanvas(int width, int height, Rgb background = rgb(0xffffff));

  void fill_rect(double x, double y, double w, double h, Rgb colour, double opacity = 1.0) override;
  void polyline(const std::vector<Point>& points, const Stroke& stroke) override;
  void marker(double x, double y, Marker shape, double size, Rgb fill, Rgb edge) override;
  void text(double x, double y, const std::string& text, Rgb colour, Anchor anchor = Anchor::kStart,
            Face face = Face::kRegular, bool vertical = false) override;

  Rgb pixel(int x, int y) const;
  const std::vector<uint8_t>& rgb_bytes() const { return pixels_; }  // row by row, 3 bytes a pixel

 private:
  void blend(int x, int y, Rgb colour, double alpha);
  void fill_polygon(const std::vector<Point>& polygon, Rgb colour);
  std::vector<uint8_t> pixels_;
};

// The PNG file (8-bit RGB, zlib-deflated, no interlace) of a raster (PNG specification, ISO/IEC
// 15948: signature, IHDR, IDAT, IEND, each chunk with its CRC-32).
std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb_bytes);

}  // namespace trackassoc::report
