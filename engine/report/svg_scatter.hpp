// A minimal SVG scatter plot (log x optional), one series per label: the plots of the Hopfield
// studies (`experiment schedules`, `seed000`), `experiment recorded` and `seed004`. The pictures of
// `run` and `associate --plots` are drawn by engine/report/association_map.hpp and
// summary_chart.hpp instead.
#pragma once

#include <string>
#include <vector>

namespace trackassoc {

struct SvgSeries {
  std::string label;
  std::vector<double> x, y;
};
std::string svg_scatter(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                        const std::vector<SvgSeries>& series, bool log_x);

}  // namespace trackassoc
