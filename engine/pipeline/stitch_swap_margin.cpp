// The swap margin of fragment stitching's joins; see engine/pipeline/stitch_swap_margin.hpp.
#include "engine/pipeline/stitch_swap_margin.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace trackassoc {

std::vector<double> stitch_swap_margins(int32_t groups, const StitchCandidates& c,
                                        std::span<const int32_t> successor) {
  const auto G = static_cast<std::size_t>(groups);
  const std::size_t n = c.end.size();
  if (c.start.size() != n || c.cost.size() != n || successor.size() != G)
    throw std::invalid_argument("stitch_swap_margins: sizes differ");
  // The candidates by end (they come sorted by end) and by start.
  std::vector<std::size_t> end_begin(G + 1, 0), start_begin(G + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && c.end[i] < c.end[i - 1])
      throw std::invalid_argument("stitch_swap_margins: not sorted by end");
    ++end_begin[static_cast<std::size_t>(c.end[i]) + 1];
    ++start_begin[static_cast<std::size_t>(c.start[i]) + 1];
  }
  for (std::size_t g = 0; g < G; ++g) end_begin[g + 1] += end_begin[g], start_begin[g + 1] += start_begin[g];
  std::vector<std::size_t> by_start(n);
  {
    std::vector<std::size_t> fill(start_begin.begin(), start_begin.end() - 1);
    for (std::size_t i = 0; i < n; ++i) by_start[fill[static_cast<std::size_t>(c.start[i])]++] = i;
  }
  std::vector<int32_t> predecessor(G, -1);
  for (std::size_t a = 0; a < G; ++a)
    if (successor[a] >= 0) predecessor[static_cast<std::size_t>(successor[a])] = static_cast<int32_t>(a);
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  auto cost = [&](int32_t a, int32_t b) {  // c(a, b), NaN when not a candidate
    for (std::size_t i = end_begin[a]; i < end_begin[a + 1]; ++i)
      if (c.start[i] == b) return c.cost[i];
    return kNone;
  };
  auto or_nothing = [](double x) { return std::isnan(x) ? 0.0 : std::min(0.0, x); };

  std::vector<double> margin(G, std::numeric_limits<double>::infinity());
  for (std::size_t a = 0; a < G; ++a) {
    const int32_t b = successor[a];
    if (b < 0) continue;
    const double chosen = cost(static_cast<int32_t>(a), b);
    if (std::isnan(chosen)) throw std::invalid_argument("stitch_swap_margins: a join is not a candidate");
    double m = std::numeric_limits<double>::infinity();
    for (std::size_t i = end_begin[a]; i < end_begin[a + 1]; ++i) {  // a takes another start b'
      if (c.start[i] == b) continue;
      const int32_t other = predecessor[static_cast<std::size_t>(c.start[i])];
      double alt = c.cost[i];
      if (other >= 0) alt += or_nothing(cost(other, b)) - cost(other, c.start[i]);
      m = std::min(m, alt - chosen);
    }
    for (std::size_t q = start_begin[b]; q < start_begin[b + 1]; ++q) {  // another end a'' takes b
      const std::size_t i = by_start[q];
      if (c.end[i] == static_cast<int32_t>(a)) continue;
      const int32_t other = successor[static_cast<std::size_t>(c.end[i])];
      double alt = c.cost[i];
      if (other >= 0) alt += or_nothing(cost(static_cast<int32_t>(a), other)) - cost(c.end[i], other);
      m = std::min(m, alt - chosen);
    }
    margin[a] = m;
  }
  return margin;
}

}  // namespace trackassoc
