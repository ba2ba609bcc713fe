// Golden-section search (Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4(3) 1953;
// Press et al., Numerical Recipes 3rd ed. §10.2): the interval [a, b] holding the minimum of a
// unimodal f, shrunk by the golden ratio 0.618 per evaluation, one new evaluation a step. On ties the
// lower part is kept. Used by covariance intersection's weight (kernels/fusion/track_fusion.cpp) and
// by the span-dependent mixture weight (kernels/statistics/mixture_weight.cpp).
#pragma once

#include <cmath>
#include <utility>

namespace trackassoc {

// The final bracket [a, b] of the minimum of f on [a, b], after the interval is at most `tolerance`
// wide or `max_steps` steps are taken, whichever comes first. 2 + steps evaluations of f.
template <class F>
std::pair<double, double> golden_section_bracket(F&& f, double a, double b, double tolerance, int max_steps) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int step = 0; step < max_steps && b - a > tolerance; ++step) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  return {a, b};
}

}  // namespace trackassoc
