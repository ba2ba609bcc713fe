// Registered reports; see engine/registration/registered_reports.hpp.
#include "engine/registration/registered_reports.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

#include "io/registration_file.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

namespace {

// The information (inverse covariance) of one plot of sensor `s` at position x: σ_range along the
// line of sight, range × σ_bearing across it (and range × σ_elevation, or σ_bearing when that is 0,
// on the third axis in 3-D). A translation model (sensor positions unknown) weighs every sensor
// alike.
Eigen::MatrixXd measurement_information(const Sensor& s, const RegistrationOptions& model,
                                        const std::vector<double>& x) {
  const int d = static_cast<int>(x.size());
  Eigen::VectorXd u(d);
  for (int i = 0; i < d; ++i) u[i] = x[i] - s.position[i];
  const double r = u.norm();
  if (!model.polar || r <= 0.0 || s.sigma_range <= 0.0 || s.sigma_bearing <= 0.0)
    return Eigen::MatrixXd::Identity(d, d);
  u /= r;
  const double cross = r * s.sigma_bearing;
  const double vertical = r * (s.sigma_elevation > 0.0 ? s.sigma_elevation : s.sigma_bearing);
  Eigen::MatrixXd P = s.sigma_range * s.sigma_range * u * u.transpose();
  if (d == 2) {
    const Eigen::Vector2d w(-u[1], u[0]);
    P += cross * cross * w * w.transpose();
  } else {
    Eigen::Vector3d w(-u[1], u[0], 0.0);
    if (w.norm() < 1e-12) w = Eigen::Vector3d(1, 0, 0);
    w.normalize();
    const Eigen::Vector3d z = Eigen::Vector3d(u[0], u[1], u[2]).cross(w);
    P += cross * cross * w * w.transpose() + vertical * vertical * z * z.transpose();
  }
  return P.inverse();
}

}  // namespace

TrackFile registered_file(const TrackFile& file, const RegistrationEstimate& e,
                          const RegistrationOptions& model, RegistrationFrame frame) {
  TrackFile out = file;
  TrackTable& t = out.tracks;
  const int D = t.dim(), d = D / 2;
  std::map<int32_t, int32_t> column;
  for (std::size_t s = 0; s < file.sensors.size(); ++s) column[file.sensors[s].id] = static_cast<int32_t>(s);
  const auto azimuth = std::find(e.parameter_names.begin(), e.parameter_names.end(), "azimuth_bias");
  const int az =
      azimuth == e.parameter_names.end() ? -1 : static_cast<int>(azimuth - e.parameter_names.begin());
  const std::size_t S = file.sensors.size();
  const bool centroid = frame == RegistrationFrame::kCentroid && S > 1;
  double mean_azimuth = 0.0;  // kCentroid: the sensors' mean azimuth bias
  if (centroid && az >= 0)
    for (std::size_t s = 0; s < S; ++s) mean_azimuth += e.sensor_bias(s)[az] / static_cast<double>(S);
  std::vector<double> x(d), v(d);
  for (std::size_t r = 0; r < t.size(); ++r) {
    const int32_t s = column.at(t.sensor[r]);
    if (s == e.reference && !centroid) continue;
    const auto b = e.sensor_bias(static_cast<std::size_t>(s));
    const auto V = e.sensor_covariance(static_cast<std::size_t>(s));
    for (int i = 0; i < d; ++i) x[i] = t.state[i][r], v[i] = t.state[d + i][r];
    const Eigen::MatrixXd J = registration_jacobian(model, d, file.sensors[s].position, x, v);
    Eigen::VectorXd dx = J * b;
    if (centroid) {  // every sensor's offset at this place, weighted by its measurement information
      Eigen::MatrixXd information = Eigen::MatrixXd::Zero(d, d);
      Eigen::VectorXd weighted = Eigen::VectorXd::Zero(d);
      for (std::size_t u = 0; u < S; ++u) {
        const Eigen::MatrixXd W = measurement_information(file.sensors[u], model, x);
        information += W;
        weighted += W * (registration_jacobian(model, d, file.sensors[u].position, x, v) * e.sensor_bias(u));
      }
      dx -= information.ldlt().solve(weighted);
    }
    for (int i = 0; i < d; ++i) t.state[i][r] -= dx[i];
    if (az >= 0) {  // the reported velocity is rotated by Δθ too: rotate it back
      const double angle = b[az] - (centroid ? mean_azimuth : 0.0);
      const double c = std::cos(angle), sn = std::sin(angle);
      t.state[d + 0][r] = c * v[0] + sn * v[1];
      t.state[d + 1][r] = -sn * v[0] + c * v[1];
    }
    const Eigen::MatrixXd W = J * V * J.transpose();
    for (int i = 0; i < d; ++i)
      for (int j = i; j < d; ++j) t.cov[packed_index(D, i, j)][r] += 0.5 * (W(i, j) + W(j, i));
  }
  return out;
}

RecordedRegistration recorded_registration(const TrackFile& file, const std::string& path,
                                           const RegistrationRecord& r) {
  const std::size_t S = file.sensors.size(), k = r.parameters.size();
  check_registration(path, r, S);
  auto fail = [&](const std::string& what, const std::string& expected, const std::string& found) {
    throw InputError(path + ": /registration/" + what + ": expected " + expected + ", found " + found);
  };
  RecordedRegistration out;
  const auto has = [&](const char* name) {
    return std::find(r.parameters.begin(), r.parameters.end(), name) != r.parameters.end();
  };
  out.model.polar = has("range_bias");
  out.model.site_offset = has("site_offset_x");
  out.model.clock_offset = has("clock_offset");
  const int32_t d = file.tracks.dim() / 2;
  const std::vector<std::string> names = registration_parameter_names(out.model, d);
  if (names != r.parameters) {
    std::string want;
    for (const auto& n : names) want += (want.empty() ? "" : ",") + n;
    fail("parameters (attribute)", "a model of the stage in " + std::to_string(d) + "-D (" + want + ")",
         std::to_string(k) + " names starting " + r.parameters.front());
  }
  RegistrationEstimate& e = out.estimate;
  e.sensors = static_cast<int32_t>(S);
  e.dim = d;
  e.reference = -1;
  e.parameter_names = r.parameters;
  e.bias.assign(S * k, 0.0);
  e.standard_error.assign(S * k, 0.0);
  e.covariance.assign(S * k * k, 0.0);
  for (std::size_t s = 0; s < S; ++s) {
    const auto it = std::find(r.sensor.begin(), r.sensor.end(), file.sensors[s].id);
    if (it == r.sensor.end())
      fail("sensor", "every /sensors id", "no row for sensor " + std::to_string(file.sensors[s].id));
    const std::size_t row = static_cast<std::size_t>(it - r.sensor.begin());
    if (file.sensors[s].id == r.reference_sensor) e.reference = static_cast<int32_t>(s);
    for (std::size_t j = 0; j < k; ++j) {
      e.bias[s * k + j] = r.estimate[row * k + j];
      e.standard_error[s * k + j] = r.standard_error[row * k + j];
      for (std::size_t l = 0; l < k; ++l)
        e.covariance[(s * k + j) * k + l] =
            !r.covariance.empty() ? r.covariance[(row * k + j) * k + l]
            : j == l              ? r.standard_error[row * k + j] * r.standard_error[row * k + j]
                                  : 0.0;
    }
  }
  if (e.reference < 0)
    fail("reference_sensor (attribute)", "a /sensors id", std::to_string(r.reference_sensor));
  return out;
}

}  // namespace trackassoc
