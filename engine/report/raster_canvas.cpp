#include "engine/report/raster_canvas.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>

#include "engine/report/font.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::report {
namespace {

double clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

// Distance from p to the segment a-b.
double distance_to_segment(Point p, Point a, Point b) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

bool inside_polygon(const std::vector<Point>& poly, double x, double y) {  // even-odd rule
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y > y) != (poly[j].y > y) &&
        x < (poly[j].x - poly[i].x) * (y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x)
      in = !in;
  return in;
}

void put_u32(std::string& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xff));
}

void put_chunk(std::string& out, const char* type, const std::string& data) {
  put_u32(out, static_cast<uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  put_u32(out, static_cast<uint32_t>(
                   crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
}

}  // namespace

int Canvas::text_width(const std::string& text, Face face) {
  return (face == Face::kBold ? bold_face() : regular_face()).text_width(text);
}

std::vector<Point> marker_outline(Marker shape, double x, double y, double size) {
  const double r = 0.5 * size;
  switch (shape) {
    case Marker::kSquare:
      return {{x - r, y - r}, {x + r, y - r}, {x + r, y + r}, {x - r, y + r}};
    case Marker::kTriangle:
      return {{x, y - r * 1.15}, {x + r * 1.1, y + r * 0.8}, {x - r * 1.1, y + r * 0.8}};
    case Marker::kTriangleDown:
      return {{x, y + r * 1.15}, {x + r * 1.1, y - r * 0.8}, {x - r * 1.1, y - r * 0.8}};
    default:  // diamond (the circle is drawn as such)
      return {{x, y - r * 1.25}, {x + r, y}, {x, y + r * 1.25}, {x - r, y}};
  }
}

std::vector<std::vector<Point>> dash_polyline(const std::vector<Point>& points,
                                              const std::vector<double>& dash) {
  if (dash.empty() || points.size() < 2) return {points};
  std::vector<std::vector<Point>> pieces;
  std::size_t phase = 0;
  double left = dash[0];  // length left in the current phase
  std::vector<Point> piece{points[0]};
  for (std::size_t i = 1; i < points.size(); ++i) {
    Point a = points[i - 1];
    const Point b = points[i];
    double seg = std::hypot(b.x - a.x, b.y - a.y);
    while (seg > left) {
      const double f = left / seg;
      a = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)};
      seg -= left;
      if (phase % 2 == 0) {
        piece.push_back(a);
        pieces.push_back(piece);
      }
      piece = {a};
      phase = (phase + 1) % dash.size();
      left = dash[phase];
    }
    left -= seg;
    if (phase % 2 == 0) piece.push_back(b);
  }
  if (phase % 2 == 0 && piece.size() >= 2) pieces.push_back(piece);
  return pieces;
}

RasterCanvas::RasterCanvas(int width, int height, Rgb background)
    : Canvas(width, height), pixels_(static_cast<std::size_t>(width) * height * 3) {
  if (width <= 0 || height <= 0) throw InputError("picture size: expected a positive width and height");
  for (std::size_t i = 0; i < pixels_.size(); i += 3) {
    pixels_[i] = background.r;
    pixels_[i + 1] = background.g;
    pixels_[i + 2] = background.b;
  }
}

Rgb RasterCanvas::pixel(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * width() + x) * 3;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void RasterCanvas::blend(int x, int y, Rgb c, double alpha) {
  if (x < 0 || y < 0 || x >= width() || y >= height() || alpha <= 0.0) return;
  alpha = std::min(alpha, 1.0);
  uint8_t* p = &pixels_[(static_cast<std::size_t>(y) * width() + x) * 3];
  auto mix = [alpha](uint8_t under, uint8_t over) {
    return static_cast<uint8_t>(std::lround(under + alpha * (static_cast<double>(over) - under)));
  };
  p[0] = mix(p[0], c.r);
  p[1] = mix(p[1], c.g);
  p[2] = mix(p[2], c.b);
}

void RasterCanvas::fill_rect(double x, double y, double w, double h, Rgb colour, double opacity) {
  // Exact area coverage of each pixel by the rectangle.
  const int x0 = static_cast<int>(std::floor(x)), x1 = static_cast<int>(std::ceil(x + w));
  const int y0 = static_cast<int>(std::floor(y)), y1 = static_cast<int>(std::ceil(y + h));
  for (int py = std::max(0, y0); py < std::min(height(), y1); ++py) {
    const double cy = std::min(py + 1.0, y + h) - std::max<double>(py, y);
    for (int px = std::max(0, x0); px < std::min(width(), x1); ++px) {
      const double cx = std::min(px + 1.0, x + w) - std::max<double>(px, x);
      blend(px, py, colour, opacity * clamp01(cx) * clamp01(cy));
    }
  }
}

void RasterCanvas::polyline(const std::vector<Point>& points, const Stroke& stroke) {
  const double half = 0.5 * std::max(stroke.width, 1.0);
  const double thin = std::min(stroke.width, 1.0);  // a hairline is a 1 px line, fainter
  for (const auto& piece : dash_polyline(points, stroke.dash)) {
    if (piece.size() < 2) continue;
    double xmin = piece[0].x, xmax = xmin, ymin = piece[0].y, ymax = ymin;
    for (const Point& p : piece) {
      xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
      ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
    }
    const int bx0 = std::max(0, static_cast<int>(std::floor(xmin - half - 1)));
    const int by0 = std::max(0, static_cast<int>(std::floor(ymin - half - 1)));
    const int bx1 = std::min(width() - 1, static_cast<int>(std::ceil(xmax + half + 1)));
    const int by1 = std::min(height() - 1, static_cast<int>(std::ceil(ymax + half + 1)));
    if (bx0 > bx1 || by0 > by1) continue;
    // The coverage of the whole piece (the largest over its segments), blended once, so joints
    // are not drawn twice.
    const int bw = bx1 - bx0 + 1, bh = by1 - by0 + 1;
    std::vector<float> cover(static_cast<std::size_t>(bw) * bh, 0.0f);
    for (std::size_t i = 1; i < piece.size(); ++i) {
      const Point a = piece[i - 1], b = piece[i];
      const int sx0 = std::max(bx0, static_cast<int>(std::floor(std::min(a.x, b.x) - half - 1)));
      const int sx1 = std::min(bx1, static_cast<int>(std::ceil(std::max(a.x, b.x) + half + 1)));
      const int sy0 = std::max(by0, static_cast<int>(std::floor(std::min(a.y, b.y) - half - 1)));
      const int sy1 = std::min(by1, static_cast<int>(std::ceil(std::max(a.y, b.y) + half + 1)));
      for (int py = sy0; py <= sy1; ++py)
        for (int px = sx0; px <= sx1; ++px) {
          const double c = clamp01(half + 0.5 - distance_to_segment({px + 0.5, py + 0.5}, a, b));
          float& cell = cover[static_cast<std::size_t>(py - by0) * bw + (px - bx0)];
          cell = std::max(cell, static_cast<float>(c));
        }
    }
    for (int py = by0; py <= by1; ++py)
      for (int px = bx0; px <= bx1; ++px)
        blend(px, py, stroke.colour,
              stroke.opacity * thin * cover[static_cast<std::size_t>(py - by0) * bw + (px - bx0)]);
  }
}

void RasterCanvas::fill_polygon(const std::vector<Point>& polygon, Rgb colour) {
  double xmin = polygon[0].x, xmax = xmin, ymin = polygon[0].y, ymax = ymin;
  for (const Point& p : polygon) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  for (int py = static_cast<int>(std::floor(ymin)); py <= static_cast<int>(std::ceil(ymax)); ++py)
    for (int px = static_cast<int>(std::floor(xmin)); px <= static_cast<int>(std::ceil(xmax)); ++px) {
      int hits = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx)
          hits += inside_polygon(polygon, px + (sx + 0.5) / 4, py + (sy + 0.5) / 4);
      blend(px, py, colour, hits / 16.0);
    }
}

void RasterCanvas::marker(double x, double y, Marker shape, double size, Rgb fill, Rgb edge) {
  const double r = 0.5 * size;
  if (shape == Marker::kCircle) {
    for (int py = static_cast<int>(y - r - 2); py <= static_cast<int>(y + r + 2); ++py)
      for (int px = static_cast<int>(x - r - 2); px <= static_cast<int>(x + r + 2); ++px) {
        const double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
        blend(px, py, fill, clamp01(r + 0.5 - d));
        blend(px, py, edge, clamp01(1.0 - std::fabs(d - r + 0.5)));  // a 1 px ring inside the edge
      }
    return;
  }
  std::vector<Point> poly = marker_outline(shape, x, y, size);
  fill_polygon(poly, fill);
  poly.push_back(poly.front());
  polyline(poly, {edge, 1.0});
}

void RasterCanvas::text(double x, double y, const std::string& text, Rgb colour, Anchor anchor, Face face,
                        bool vertical) {
  const FontFace& font = face == Face::kBold ? bold_face() : regular_face();
  const int w = font.text_width(text);
  const double shift = anchor == Anchor::kStart ? 0.0 : anchor == Anchor::kMiddle ? 0.5 * w : w;
  // Pen position along the text; pixels are placed whole (the glyphs are already antialiased).
  int pen = static_cast<int>(std::lround(-shift));
  const int ox = static_cast<int>(std::lround(x)), oy = static_cast<int>(std::lround(y));
  for (char c : text) {
    const Glyph& g = font.glyph(c);
    for (int row = 0; row < g.height; ++row)
      for (int col = 0; col < g.width; ++col) {
        const char h = g.coverage[row * g.width + col];
        const int level = h <= '9' ? h - '0' : h - 'a' + 10;
        if (level == 0) continue;
        const int u = pen + g.dx + col, v = g.dy + row;  // along the text, down from the baseline
        if (vertical)
          blend(ox + v, oy - u, colour, level / 15.0);
        else
          blend(ox + u, oy + v, colour, level / 15.0);
      }
    pen += g.advance;
  }
}

std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb_bytes) {
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  if (width <= 0 || height <= 0 || rgb_bytes.size() != row * height)
    throw InputError("PNG: expected " + std::to_string(width) + " x " + std::to_string(height) +
                     " RGB pixels, found " + std::to_string(rgb_bytes.size()) + " bytes");
  std::string raw;  // each row after its filter byte (0: none)
  raw.reserve((row + 1) * height);
  for (int y = 0; y < height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(&rgb_bytes[y * row]), row);
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()), 9) != Z_OK)
    throw std::runtime_error("PNG: zlib could not compress the picture");
  packed.resize(packed_size);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put_u32(header, static_cast<uint32_t>(width));
  put_u32(header, static_cast<uint32_t>(height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  put_chunk(png, "IHDR", header);
  put_chunk(png, "IDAT", packed);
  put_chunk(png, "IEND", "");
  return png;
}

}  // namespace trackassoc::report
