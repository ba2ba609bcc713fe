#include "kernels/filters/kalman_converted.hpp"

#include <cmath>

namespace trackassoc {

ConvertedMeasurement convert_polar(int d, const Sensor& s, double r, double th, double el) {
  ConvertedMeasurement m;
  const double sr2 = s.sigma_range * s.sigma_range, sb2 = s.sigma_bearing * s.sigma_bearing;
  const double ct = std::cos(th), st = std::sin(th);
  if (d == 2) {
    m.z = {s.position[0] + r * ct, s.position[1] + r * st, 0.0};
    // J = [[cos θ, −r sin θ], [sin θ, r cos θ]]  (Lerro & Bar-Shalom 1993, Eq. 4)
    const double r2 = r * r;
    m.R[0] = sr2 * ct * ct + r2 * sb2 * st * st;
    m.R[1] = (sr2 - r2 * sb2) * st * ct;
    m.R[2] = sr2 * st * st + r2 * sb2 * ct * ct;
    return m;
  }
  const double se2 = s.sigma_elevation * s.sigma_elevation;
  const double ce = std::cos(el), se = std::sin(el);
  m.z = {s.position[0] + r * ce * ct, s.position[1] + r * ce * st, s.position[2] + r * se};
  // Columns of J: ∂/∂r, ∂/∂θ, ∂/∂φ.
  const double J[3][3] = {
      {ce * ct, -r * ce * st, -r * se * ct}, {ce * st, r * ce * ct, -r * se * st}, {se, 0.0, r * ce}};
  const double v[3] = {sr2, sb2, se2};
  int k = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b, ++k) {
      double acc = 0.0;
      for (int c = 0; c < 3; ++c) acc += J[a][c] * v[c] * J[b][c];
      m.R[k] = acc;
    }
  return m;
}

PolarPoint cartesian_to_polar(int d, const Sensor& s, const std::array<double, 3>& p) {
  const double dx = p[0] - s.position[0], dy = p[1] - s.position[1];
  const double horizontal = std::hypot(dx, dy);
  PolarPoint q;
  q.bearing = std::atan2(dy, dx);
  if (d == 2) {
    q.range = horizontal;
    return q;
  }
  const double dz = p[2] - s.position[2];
  q.range = std::sqrt(horizontal * horizontal + dz * dz);
  q.elevation = std::atan2(dz, horizontal);
  return q;
}

}  // namespace trackassoc
