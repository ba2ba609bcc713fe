// Leave-one-out histogram density; see kernels/statistics/histogram_density.hpp.
#include "kernels/statistics/histogram_density.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace trackassoc {

std::vector<double> leave_one_out_log_density(std::span<const double> samples) {
  const std::size_t G = samples.size();
  if (G == 0) return {};
  const auto [lo_it, hi_it] = std::minmax_element(samples.begin(), samples.end());
  const double lo = *lo_it, width = std::max(*hi_it - lo, 1.0);
  const std::size_t B = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(G))));
  auto bin_of = [&](double x) {
    const double u = (x - lo) / width * static_cast<double>(B);
    return u >= 0.0 ? std::min(B - 1, static_cast<std::size_t>(u)) : std::size_t{0};
  };
  std::vector<double> count(B, 1.0);  // one count added to each bin (Laplace)
  for (double x : samples) count[bin_of(x)] += 1.0;
  const double bin_width = width / static_cast<double>(B), others = static_cast<double>(G - 1 + B);
  std::vector<double> log_density(G);
  for (std::size_t g = 0; g < G; ++g)
    log_density[g] = std::log((count[bin_of(samples[g])] - 1.0) / (others * bin_width));
  return log_density;
}

}  // namespace trackassoc
