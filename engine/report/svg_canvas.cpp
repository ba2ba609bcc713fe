#include "engine/report/svg_canvas.hpp"

#include <cstdio>

namespace trackassoc::report {
namespace {

std::string hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126)
      out += '?';
    else
      out += c;
  }
  return out;
}

std::string points_attribute(const std::vector<Point>& points) {
  std::string s;
  for (const Point& p : points) {
    if (!s.empty()) s += ' ';
    s += num(p.x);
    s += ',';
    s += num(p.y);
  }
  return s;
}

}  // namespace

SvgCanvas::SvgCanvas(int width, int height, Rgb background) : Canvas(width, height) {
  fill_rect(0, 0, width, height, background);
}

void SvgCanvas::fill_rect(double x, double y, double w, double h, Rgb colour, double opacity) {
  body_ << "<rect x='" << num(x) << "' y='" << num(y) << "' width='" << num(w) << "' height='" << num(h)
        << "' fill='" << hex(colour) << "'";
  if (opacity < 1.0) body_ << " fill-opacity='" << num(opacity) << "'";
  body_ << "/>\n";
}

void SvgCanvas::polyline(const std::vector<Point>& points, const Stroke& stroke) {
  if (points.size() < 2) return;
  body_ << "<polyline fill='none' stroke='" << hex(stroke.colour) << "' stroke-width='" << num(stroke.width)
        << "' stroke-linejoin='round' stroke-linecap='round'";
  if (stroke.opacity < 1.0) body_ << " stroke-opacity='" << num(stroke.opacity) << "'";
  if (!stroke.dash.empty()) {
    body_ << " stroke-dasharray='";
    for (std::size_t i = 0; i < stroke.dash.size(); ++i) body_ << (i ? "," : "") << num(stroke.dash[i]);
    body_ << "'";
  }
  body_ << " points='" << points_attribute(points) << "'/>\n";
}

void SvgCanvas::marker(double x, double y, Marker shape, double size, Rgb fill, Rgb edge) {
  const double r = 0.5 * size;
  std::ostringstream paint_text;
  paint_text << "fill='" << hex(fill) << "' stroke='" << hex(edge) << "' stroke-width='1'";
  const std::string paint = paint_text.str();
  if (shape == Marker::kCircle) {
    body_ << "<circle cx='" << num(x) << "' cy='" << num(y) << "' r='" << num(r) << "' " << paint << "/>\n";
    return;
  }
  const std::vector<Point> poly = marker_outline(shape, x, y, size);
  body_ << "<polygon points='" << points_attribute(poly) << "' " << paint << "/>\n";
}

void SvgCanvas::text(double x, double y, const std::string& text, Rgb colour, Anchor anchor, Face face,
                     bool vertical) {
  const char* a = anchor == Anchor::kStart ? "start" : anchor == Anchor::kMiddle ? "middle" : "end";
  body_ << "<text x='" << num(x) << "' y='" << num(y) << "' fill='" << hex(colour) << "' text-anchor='" << a
        << "'" << (face == Face::kBold ? " font-size='16' font-weight='bold'" : "");
  if (vertical) body_ << " transform='rotate(-90 " << num(x) << " " << num(y) << ")'";
  body_ << ">" << escaped(text) << "</text>\n";
}

std::string SvgCanvas::document() const {
  std::ostringstream doc;
  doc << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width() << "' height='" << height()
      << "' viewBox='0 0 " << width() << " " << height()
      << "' font-family='DejaVu Sans, Verdana, sans-serif' font-size='13'>\n"
      << body_.str() << "</svg>\n";
  return doc.str();
}

}  // namespace trackassoc::report
