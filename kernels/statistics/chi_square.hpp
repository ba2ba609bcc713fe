// Chi-square quantiles for the association gates (docs/design.md §4.3): seed 000's χ²(n·D) gate and the
// calibrated gate's f·χ²(n·D/f), whose effective degrees of freedom are fractional.
//
// Algorithm: the regularised lower incomplete gamma P(dof/2, x/2) by its series (x < a + 1) or
// continued fraction (modified Lentz), Numerical Recipes §6.2; the quantile from the
// Wilson–Hilferty start refined by Newton steps on P. O(1) per call (at most ~1000 terms).
#pragma once

namespace trackassoc {

// The x with P(χ²_dof ≤ x) = p, for p in (0, 1) and dof > 0.
double chi_square_quantile(double p, int dof);
double chi_square_quantile(double p, double dof);  // fractional degrees of freedom

}  // namespace trackassoc
