// The per-scan bound of the calibrated gate; see kernels/statistics/scan_bound.hpp.
#include "kernels/statistics/scan_bound.hpp"

#include <algorithm>
#include <cmath>

namespace trackassoc {

namespace {

// d_pᵀ C_pp⁻¹ d_p ≤ c2 for C_pp = the sum of the position blocks pa, pb, by the adjugate (m = 2
// or 3, no square root): a superset, by a relative 10⁻⁹, of the prune's Cholesky test
// (kernels/statistics/gate_candidates.cpp), so that nothing the prune counts within is missed.
// True when C_pp is not positive definite.
bool within_ellipse(const double* d, const double* pa, const double* pb, int m, double c2) {
  const double bound = c2 * (1.0 + 1e-9);
  if (m == 2) {
    const double a = pa[0] + pb[0], b = pa[1] + pb[1], e = pa[2] + pb[2], det = a * e - b * b;
    if (!(a > 0.0) || !(det > 0.0)) return true;
    return d[0] * d[0] * e - 2.0 * d[0] * d[1] * b + d[1] * d[1] * a <= bound * det;
  }
  if (m == 3) {
    const double a = pa[0] + pb[0], b = pa[1] + pb[1], c = pa[2] + pb[2], e = pa[3] + pb[3],
                 f = pa[4] + pb[4], g = pa[5] + pb[5];
    const double A = e * g - f * f, B = c * f - b * g, Cc = b * f - c * e;  // first row of the adjugate
    const double det = a * A + b * B + c * Cc, minor2 = a * e - b * b;
    if (!(a > 0.0) || !(minor2 > 0.0) || !(det > 0.0)) return true;
    const double E = a * g - c * c, F = b * c - a * f;
    const double q = d[0] * d[0] * A + d[1] * d[1] * E + d[2] * d[2] * minor2 +
                     2.0 * (d[0] * d[1] * B + d[0] * d[2] * Cc + d[1] * d[2] * F);
    return q <= bound * det;
  }
  return true;  // (m = 1: the circle is the ellipse, widened as the spreads are)
}

}  // namespace

void position_block(const double* packed, int D, int m, double* out) {
  int k = 0;
  for (int r = 0; r < m; ++r)
    for (int c = r; c < m; ++c) out[k++] = packed[packed_index(D, r, c)];
}

double position_spread(const double* block, int m) {
  constexpr double kWiden = 1.0 + 1e-8;
  if (m == 1) return block[0] * kWiden;
  if (m == 2) {
    const double xx = block[0], xy = block[1], yy = block[2], trace = xx + yy;
    if (std::isnan(trace + xy)) return trace;
    const double gershgorin = std::max(xx, yy) + std::abs(xy);
    const bool semi_definite = xx >= 0.0 && yy >= 0.0 && xx * yy >= xy * xy;
    return (trace < gershgorin && semi_definite ? trace : gershgorin) * kWiden;
  }
  const double xx = block[0], xy = block[1], xz = block[2], yy = block[3], yz = block[4], zz = block[5];
  const double trace = xx + yy + zz;
  if (std::isnan(trace + xy + xz + yz)) return trace;
  const double gershgorin = std::max(
      {xx + std::abs(xy) + std::abs(xz), yy + std::abs(xy) + std::abs(yz), zz + std::abs(xz) + std::abs(yz)});
  if (!(trace < gershgorin)) return gershgorin * kWiden;  // (the usual case; no minors needed)
  const double det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  const bool semi_definite = xx >= 0.0 && yy >= 0.0 && zz >= 0.0 && xx * yy >= xy * xy &&
                             xx * zz >= xz * xz && yy * zz >= yz * yz && det >= 0.0;
  return (semi_definite ? trace : gershgorin) * kWiden;
}

bool within_points(const double* xa, double sa, const double* pa, const double* xb, double sb,
                   const double* pb, int m, double c2) {
  double d[3] = {}, d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    d[c] = xa[c] - xb[c];
    d2 += d[c] * d[c];
  }
  if (!(d2 <= (sa + sb) * c2)) return false;
  return within_ellipse(d, pa, pb, m, c2);
}

bool within_scan_bound(const AlignedTracks& a, int64_t ca, const AlignedTracks& b, int64_t cb, int m,
                       double c2) {
  const int D = a.dim;
  double pa[kPositionBlock], pb[kPositionBlock];
  position_block(a.cov_at(ca), D, m, pa);
  position_block(b.cov_at(cb), D, m, pb);
  return within_points(a.state_at(ca), position_spread(pa, m), pa, b.state_at(cb), position_spread(pb, m), pb,
                       m, c2);
}

}  // namespace trackassoc
