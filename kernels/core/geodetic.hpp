// WGS-84 geodetic coordinates to a local east-north-up (ENU) frame.
//
// Algorithm: geodetic (φ, λ, h) → Earth-centred Earth-fixed (ECEF) with the prime-vertical radius
// N(φ) = a / sqrt(1 − e² sin²φ):
//   X = (N + h) cos φ cos λ,  Y = (N + h) cos φ sin λ,  Z = (N (1 − e²) + h) sin φ,
// then the difference to the origin's ECEF point rotated into the origin's tangent plane:
//   e = −sin λ₀ dX + cos λ₀ dY
//   n = −sin φ₀ cos λ₀ dX − sin φ₀ sin λ₀ dY + cos φ₀ dZ
//   u =  cos φ₀ cos λ₀ dX + cos φ₀ sin λ₀ dY + sin φ₀ dZ
// (Hofmann-Wellenhof, Lichtenegger and Wasle, "GNSS", 2008, §5.6.1 and §10.2.2; the same as
// MATLAB's geodetic2enu and pymap3d.geodetic2enu). Exact: no flat-Earth approximation, so it holds
// for any distance from the origin, but the frame is the origin's tangent plane, and far from it
// "up" is not the local vertical. O(1) per point; the origin's trigonometry is computed once.
// WGS-84: a = 6 378 137 m, f = 1/298.257223563 (NIMA TR8350.2, 2000, Table 3.1).
#pragma once

#include <array>

namespace trackassoc {

inline constexpr double kWgs84A = 6378137.0;                 // semi-major axis [m]
inline constexpr double kWgs84F = 1.0 / 298.257223563;       // flattening
inline constexpr double kWgs84E2 = kWgs84F * (2 - kWgs84F);  // first eccentricity squared

// Earth-centred Earth-fixed position [m] of latitude, longitude [deg] and height above the
// ellipsoid [m].
std::array<double, 3> geodetic_to_ecef(double lat_deg, double lon_deg, double alt_m);

// The local ENU frame whose origin is a geodetic point.
class EnuFrame {
 public:
  EnuFrame(double lat0_deg, double lon0_deg, double alt0_m);
  // East, north, up [m] of a geodetic point.
  std::array<double, 3> enu(double lat_deg, double lon_deg, double alt_m) const;
  double origin_lat_deg() const { return lat0_; }
  double origin_lon_deg() const { return lon0_; }
  double origin_alt_m() const { return alt0_; }

 private:
  double lat0_, lon0_, alt0_;
  std::array<double, 3> origin_ecef_;
  double sin_lat_, cos_lat_, sin_lon_, cos_lon_;
};

}  // namespace trackassoc
