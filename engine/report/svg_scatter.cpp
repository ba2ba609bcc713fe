#include "engine/report/svg_scatter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace trackassoc {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

std::string svg_scatter(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                        const std::vector<SvgSeries>& series, bool log_x) {
  const double W = 900, H = 560, L = 80, R = 260, T = 40, B = 60;
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  auto tx = [&](double x) { return log_x ? std::log10(std::max(x, 1e-9)) : x; };
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      xmin = std::min(xmin, tx(s.x[i]));
      xmax = std::max(xmax, tx(s.x[i]));
      ymin = std::min(ymin, s.y[i]);
      ymax = std::max(ymax, s.y[i]);
    }
  if (!(xmin < xmax)) {
    xmin -= 1;
    xmax += 1;
  }
  if (!(ymin < ymax)) {
    ymin -= 1;
    ymax += 1;
  }
  const double px = (W - L - R) / (xmax - xmin), py = (H - T - B) / (ymax - ymin);
  auto X = [&](double x) { return L + (tx(x) - xmin) * px; };
  auto Y = [&](double y) { return H - B - (y - ymin) * py; };
  static const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
                                  "#000000", "#aa0000", "#00aa00", "#0000aa"};
  std::ostringstream os;
  os << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
     << "' font-family='sans-serif' font-size='12'>\n";
  os << "<rect width='100%' height='100%' fill='white'/>\n";
  os << "<text x='" << W / 2 << "' y='22' text-anchor='middle' font-size='15'>" << title << "</text>\n";
  os << "<line x1='" << L << "' y1='" << H - B << "' x2='" << W - R << "' y2='" << H - B
     << "' stroke='black'/>\n";
  os << "<line x1='" << L << "' y1='" << T << "' x2='" << L << "' y2='" << H - B << "' stroke='black'/>\n";
  for (int t = 0; t <= 5; ++t) {
    const double xv = xmin + (xmax - xmin) * t / 5, yv = ymin + (ymax - ymin) * t / 5;
    const double xs = L + (xv - xmin) * px, ys = H - B - (yv - ymin) * py;
    os << "<text x='" << xs << "' y='" << H - B + 18 << "' text-anchor='middle'>"
       << (log_x ? number(std::pow(10.0, xv)) : number(xv)) << "</text>\n";
    os << "<text x='" << L - 6 << "' y='" << ys + 4 << "' text-anchor='end'>" << number(yv) << "</text>\n";
    os << "<line x1='" << L << "' y1='" << ys << "' x2='" << W - R << "' y2='" << ys << "' stroke='#ddd'/>\n";
  }
  os << "<text x='" << (L + W - R) / 2 << "' y='" << H - 15 << "' text-anchor='middle'>" << xlabel
     << "</text>\n";
  os << "<text x='18' y='" << (T + H - B) / 2 << "' text-anchor='middle' transform='rotate(-90 18 "
     << (T + H - B) / 2 << ")'>" << ylabel << "</text>\n";
  for (std::size_t s = 0; s < series.size(); ++s) {
    const char* col = colours[s % (sizeof colours / sizeof colours[0])];
    for (std::size_t i = 0; i < series[s].x.size(); ++i)
      os << "<circle cx='" << X(series[s].x[i]) << "' cy='" << Y(series[s].y[i]) << "' r='3.5' fill='" << col
         << "' fill-opacity='0.75'/>\n";
    const double ly = T + 16 * s + 10;
    os << "<circle cx='" << W - R + 16 << "' cy='" << ly << "' r='4' fill='" << col << "'/>";
    os << "<text x='" << W - R + 26 << "' y='" << ly + 4 << "'>" << series[s].label << "</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace trackassoc
