// EM for a two-component mixture's weight; see kernels/statistics/mixture_weight.hpp.
#include "kernels/statistics/mixture_weight.hpp"

#include <algorithm>
#include <cmath>

namespace trackassoc {

double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight) {
  if (!(prior > 0.0 && prior < 1.0) || log_ratios.empty()) return prior;
  constexpr double kFloor = 1e-6;
  const double n = static_cast<double>(log_ratios.size());
  double pi = prior;
  for (int step = 0; step < 200; ++step) {
    const double log_odds = std::log(pi) - std::log1p(-pi);
    double responsibility = 0.0;
    for (float d : log_ratios) responsibility += 1.0 / (1.0 + std::exp(-(log_odds + d)));
    const double next =
        std::clamp((responsibility + prior_weight * prior) / (n + prior_weight), kFloor, 1.0 - kFloor);
    const bool converged = std::fabs(next - pi) < 1e-9;
    pi = next;
    if (converged) break;
  }
  return pi;
}

}  // namespace trackassoc
