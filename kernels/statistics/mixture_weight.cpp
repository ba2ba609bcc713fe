// A two-component mixture's weight by bisection on the score; see kernels/statistics/mixture_weight.hpp.
#include "kernels/statistics/mixture_weight.hpp"

#include <cmath>

namespace trackassoc {

double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight) {
  if (!(prior > 0.0 && prior < 1.0) || log_ratios.empty()) return prior;
  // ℓ'(π): each sample's (e^d − 1) / (1 − π + π e^d), written for d > 0 as (1 − e^−d) / ((1 − π) e^−d + π)
  // so that neither form overflows.
  auto score = [&](double pi) {
    double s = prior_weight * prior / pi - prior_weight * (1.0 - prior) / (1.0 - pi);
    for (float value : log_ratios) {
      const double d = value;
      if (d > 0.0) {
        const double e = std::exp(-d);
        s += (1.0 - e) / ((1.0 - pi) * e + pi);
      } else {
        const double e = std::exp(d);
        s += (e - 1.0) / (1.0 - pi + pi * e);
      }
    }
    return s;
  };
  constexpr double kFloor = 1e-6;
  double lo = kFloor, hi = 1.0 - kFloor;
  const double at_lo = score(lo), at_hi = score(hi);
  if (at_lo == 0.0 && at_hi == 0.0) return prior;  // ℓ flat: nothing tells π apart
  if (at_lo <= 0.0) return lo;
  if (at_hi >= 0.0) return hi;
  for (int halving = 0; halving < 60; ++halving) {
    const double mid = 0.5 * (lo + hi);
    (score(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace trackassoc
