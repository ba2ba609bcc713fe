// A Canvas written as SVG elements (the pictures with --svg): the same primitives as the raster,
// in the font the raster's glyphs come from (DejaVu Sans), so the layout measured with the
// built-in font (Canvas::text_width) holds in both.
#pragma once

#include <sstream>
#include <string>

#include "engine/report/canvas.hpp"

namespace trackassoc::report {

class SvgCanvas final : public Canvas {
 public:
  SvgCanvas(int width, int height, Rgb background = rgb(0xffffff));

  void fill_rect(double x, double y, double w, double h, Rgb colour, double opacity = 1.0) override;
  void polyline(const std::vector<Point>& points, const Stroke& stroke) override;
  void marker(double x, double y, Marker shape, double size, Rgb fill, Rgb edge) override;
  void text(double x, double y, const std::string& text, Rgb colour, Anchor anchor = Anchor::kStart,
            Face face = Face::kRegular, bool vertical = false) override;

  std::string document() const;  // the whole SVG file

 private:
  std::ostringstream body_;
};

}  // namespace trackassoc::report
