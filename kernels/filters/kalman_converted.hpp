// Polar-to-Cartesian converted measurements for the position Kalman update (docs/design.md §4.1).
//
// Algorithm. The linearised converted measurement (CM) of Lerro & Bar-Shalom, "Tracking with
// debiased consistent converted measurements versus EKF", IEEE T-AES 29(3), 1993, §II (also
// Bar-Shalom, Li, Kirubarajan 2001, §10.4.3):
//   2-D  z = s + r [cos θ, sin θ]
//   3-D  z = s + r [cos φ cos θ, cos φ sin θ, sin φ]
//   R = J diag(σ_r², σ_θ², σ_φ²) Jᵀ,  J = ∂z/∂(r, θ, φ) evaluated at the measured (r, θ, φ).
// The conversion bias is r·σ_θ²/2 and is negligible while r·σ_θ²/σ_r < 0.4 (Lerro & Bar-Shalom's
// criterion), which holds for every scenario shipped with trackassoc (seed 000: 200 km·(1°)²/170 m
// ≈ 0.36). Conventions: bearing θ = atan2(Δy, Δx) counter-clockwise from the +x axis; elevation
// φ = atan2(Δz, horizontal range); in 2-D the range is horizontal and z is ignored.
// Complexity O(1) per measurement.
#pragma once

#include <array>

#include "kernels/core/types.hpp"

namespace trackassoc {

struct ConvertedMeasurement {
  std::array<double, 3> z{0, 0, 0};           // Cartesian position, first d entries used
  std::array<double, 6> R{0, 0, 0, 0, 0, 0};  // packed upper triangle of the d×d covariance
};

// d = 2 or 3. elevation is ignored in 2-D.
ConvertedMeasurement convert_polar(int d, const Sensor& sensor, double range, double bearing,
                                   double elevation);

// The inverse, noise-free: the polar coordinates of Cartesian point p seen from `sensor`.
struct PolarPoint {
  double range = 0, bearing = 0, elevation = 0;
};
PolarPoint cartesian_to_polar(int d, const Sensor& sensor, const std::array<double, 3>& p);

}  // namespace trackassoc
