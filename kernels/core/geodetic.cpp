#include "kernels/core/geodetic.hpp"

#include <cmath>
#include <numbers>

namespace trackassoc {
namespace {
constexpr double kDegree = std::numbers::pi / 180.0;
}  // namespace

std::array<double, 3> geodetic_to_ecef(double lat_deg, double lon_deg, double alt_m) {
  const double lat = lat_deg * kDegree, lon = lon_deg * kDegree;
  const double s = std::sin(lat), c = std::cos(lat);
  const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);  // prime-vertical radius of curvature
  return {(n + alt_m) * c * std::cos(lon), (n + alt_m) * c * std::sin(lon),
          (n * (1.0 - kWgs84E2) + alt_m) * s};
}

EnuFrame::EnuFrame(double lat0_deg, double lon0_deg, double alt0_m)
    : lat0_(lat0_deg),
      lon0_(lon0_deg),
      alt0_(alt0_m),
      origin_ecef_(geodetic_to_ecef(lat0_deg, lon0_deg, alt0_m)),
      sin_lat_(std::sin(lat0_deg * kDegree)),
      cos_lat_(std::cos(lat0_deg * kDegree)),
      sin_lon_(std::sin(lon0_deg * kDegree)),
      cos_lon_(std::cos(lon0_deg * kDegree)) {}

std::array<double, 3> EnuFrame::enu(double lat_deg, double lon_deg, double alt_m) const {
  const std::array<double, 3> p = geodetic_to_ecef(lat_deg, lon_deg, alt_m);
  const double dx = p[0] - origin_ecef_[0], dy = p[1] - origin_ecef_[1], dz = p[2] - origin_ecef_[2];
  return {-sin_lon_ * dx + cos_lon_ * dy,
          -sin_lat_ * cos_lon_ * dx - sin_lat_ * sin_lon_ * dy + cos_lat_ * dz,
          cos_lat_ * cos_lon_ * dx + cos_lat_ * sin_lon_ * dy + sin_lat_ * dz};
}

}  // namespace trackassoc
