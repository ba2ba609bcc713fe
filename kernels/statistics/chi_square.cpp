// Chi-square quantiles for the association gate (docs/design.md §4.3), for integer and fractional degrees
// of freedom (the calibrated gate's effective dof n·D/f is fractional).
#include "kernels/statistics/chi_square.hpp"

#include <cmath>

#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// Regularised lower incomplete gamma P(a, x), by series for x < a + 1 and by the continued
// fraction (modified Lentz) otherwise (Numerical Recipes §6.2).
double regularized_gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double chi_square_quantile(double p, int dof) { return chi_square_quantile(p, static_cast<double>(dof)); }

double chi_square_quantile(double p, double dof) {
  // (Messages made only on failure: the gate asks for hundreds of quantiles per pair of sensors,
  // and formatting two numbers each time was 1-2 % of an association.)
  require(std::isfinite(dof) && dof > 0, "chi_square_quantile",
          [&] { return "degrees of freedom must be positive, got " + std::to_string(dof); });
  require(p > 0.0 && p < 1.0, "chi_square_quantile",
          [&] { return "probability must be in (0, 1), got " + std::to_string(p); });
  const double k = dof;
  // Wilson–Hilferty start: x ≈ k (1 − 2/(9k) + z √(2/(9k)))³, z the normal quantile (Acklam-free:
  // a bisection-safe Newton refinement below makes the start's accuracy unimportant).
  const double z = std::sqrt(2.0) * [&] {
    // inverse error function of 2p−1 by Newton on erf
    double y = 0.0, target = 2.0 * p - 1.0;
    for (int i = 0; i < 60; ++i) {
      const double f = std::erf(y) - target;
      y -= f / (2.0 / std::sqrt(M_PI) * std::exp(-y * y));
      if (std::fabs(f) < 1e-15) break;
    }
    return y;
  }();
  double x = k * std::pow(std::max(1e-3, 1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k))), 3.0);
  double lo = 0.0, hi = std::max(2.0 * x, k + 40.0 * std::sqrt(2.0 * k) + 100.0);
  for (int i = 0; i < 200; ++i) {
    const double f = regularized_gamma_p(0.5 * k, 0.5 * x) - p;
    if (std::fabs(f) < 1e-14) break;
    if (f > 0)
      hi = x;
    else
      lo = x;
    const double log_pdf =
        (0.5 * k - 1.0) * std::log(x) - 0.5 * x - 0.5 * k * std::log(2.0) - std::lgamma(0.5 * k);
    double next = x - f / std::exp(log_pdf);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - x) < 1e-12 * std::max(1.0, x)) {
      x = next;
      break;
    }
    x = next;
  }
  return x;
}

}  // namespace trackassoc
