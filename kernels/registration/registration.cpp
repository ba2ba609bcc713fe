// Relative sensor registration; see kernels/registration/registration.hpp.
#include "kernels/registration/registration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void RegistrationOptions::validate() const {
  const std::string w = "RegistrationOptions.";
  require(reference_sensor >= 0, w + "reference_sensor", "expected a sensor index >= 0");
  require(polar || site_offset || clock_offset, w + "polar",
          "expected at least one of polar, site_offset, clock_offset");
  for (auto [v, name] : {std::pair{prior_range, "prior_range"},
                         {prior_azimuth, "prior_azimuth"},
                         {prior_elevation, "prior_elevation"},
                         {prior_site_offset, "prior_site_offset"},
                         {prior_clock, "prior_clock"},
                         {huber, "huber"}})
    require(std::isfinite(v) && v > 0.0, w + name, "expected a finite value > 0");
  require(iterations >= 1 && iterations <= 100, w + "iterations", "expected 1..100");
}

void RegistrationObservations::add(int32_t a, int32_t b, int64_t pair, std::span<const double> x_a,
                                   std::span<const double> x_b, std::span<const double> v_a,
                                   std::span<const double> v_b, std::span<const double> c) {
  const std::size_t d = static_cast<std::size_t>(dim);
  sensor_a.push_back(a);
  sensor_b.push_back(b);
  cluster.push_back(pair);
  for (std::size_t i = 0; i < d; ++i) {
    position_a.push_back(x_a[i]);
    position_b.push_back(x_b[i]);
    velocity_a.push_back(v_a.empty() ? 0.0 : v_a[i]);
    velocity_b.push_back(v_b.empty() ? 0.0 : v_b[i]);
  }
  for (std::size_t i = 0; i < d * d; ++i) covariance.push_back(c[i]);
}

std::vector<std::string> registration_parameter_names(const RegistrationOptions& o, int32_t d) {
  std::vector<std::string> names;
  if (o.polar) {
    names.push_back("range_bias");
    names.push_back("azimuth_bias");
    if (d == 3) names.push_back("elevation_bias");
  }
  if (o.site_offset || !o.polar) {
    names.push_back("site_offset_x");
    names.push_back("site_offset_y");
    if (d == 3) names.push_back("site_offset_z");
  }
  if (o.clock_offset) names.push_back("clock_offset");
  return names;
}

namespace {

std::vector<double> prior_sigmas(const RegistrationOptions& o, int32_t d) {
  std::vector<double> sigma;
  for (const auto& n : registration_parameter_names(o, d)) {
    if (n == "range_bias")
      sigma.push_back(o.prior_range);
    else if (n == "azimuth_bias")
      sigma.push_back(o.prior_azimuth);
    else if (n == "elevation_bias")
      sigma.push_back(o.prior_elevation);
    else if (n == "clock_offset")
      sigma.push_back(o.prior_clock);
    else
      sigma.push_back(o.prior_site_offset);
  }
  return sigma;
}

}  // namespace

Eigen::MatrixXd registration_jacobian(const RegistrationOptions& o, int32_t d,
                                      const std::array<double, 3>& site, std::span<const double> x,
                                      std::span<const double> v) {
  const int k = static_cast<int>(registration_parameter_names(o, d).size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(d, k);
  int c = 0;
  if (o.polar) {
    double rel[3] = {0, 0, 0};
    for (int i = 0; i < d; ++i) rel[i] = x[i] - site[i];
    const double rho = std::hypot(rel[0], rel[1]);
    const double r = d == 3 ? std::sqrt(rho * rho + rel[2] * rel[2]) : rho;
    const double safe_r = std::max(r, 1e-9), safe_rho = std::max(rho, 1e-9);
    for (int i = 0; i < d; ++i) J(i, c) = rel[i] / safe_r;  // ∂x/∂r
    ++c;
    J(0, c) = -rel[1];  // ∂x/∂θ, θ counter-clockwise from +x
    J(1, c) = rel[0];
    ++c;
    if (d == 3) {  // ∂x/∂φ
      J(0, c) = -rel[2] * rel[0] / safe_rho;
      J(1, c) = -rel[2] * rel[1] / safe_rho;
      J(2, c) = rho;
      ++c;
    }
  }
  if (o.site_offset || !o.polar)
    for (int i = 0; i < d; ++i, ++c) J(i, c) = -1.0;  // the sensor reports x − o
  if (o.clock_offset) {
    for (int i = 0; i < d; ++i) J(i, c) = v.empty() ? 0.0 : -v[i];  // x(t − Δt) ≈ x(t) − v·Δt
    ++c;
  }
  return J;
}

double RegistrationEstimate::wald(int32_t& dof) const {
  const int32_t K = k();
  double w = 0.0;
  dof = 0;
  for (int32_t s = 0; s < sensors; ++s) {
    if (s == reference) continue;
    const auto b = sensor_bias(static_cast<std::size_t>(s));
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(sensor_covariance(static_cast<std::size_t>(s)));
    if (ldlt.info() != Eigen::Success) continue;
    w += b.dot(ldlt.solve(b));
    dof += K;
  }
  return w;
}

RegistrationEstimate fit_registration(const RegistrationObservations& obs,
                                      std::span<const std::array<double, 3>> sites,
                                      const RegistrationOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  o.validate();
  const int32_t S = static_cast<int32_t>(sites.size()), d = obs.dim;
  require(d == 2 || d == 3, "fit_registration: observations.dim",
          "expected 2 or 3, found " + std::to_string(d));
  require(
      o.reference_sensor < S, "RegistrationOptions.reference_sensor",
      "expected a sensor index below " + std::to_string(S) + ", found " + std::to_string(o.reference_sensor));
  const std::size_t N = obs.size();
  require(obs.sensor_b.size() == N && obs.cluster.size() == N && obs.position_a.size() == N * d &&
              obs.position_b.size() == N * d && obs.covariance.size() == N * d * d,
          "fit_registration: observations", "expected columns of equal length");
  for (std::size_t i = 0; i < N; ++i)
    require(obs.sensor_a[i] >= 0 && obs.sensor_a[i] < S && obs.sensor_b[i] >= 0 && obs.sensor_b[i] < S &&
                obs.sensor_a[i] != obs.sensor_b[i],
            "fit_registration: observation " + std::to_string(i),
            "expected two different sensors in 0.." + std::to_string(S - 1));

  RegistrationEstimate est;
  est.sensors = S;
  est.dim = d;
  est.reference = o.reference_sensor;
  est.parameter_names = registration_parameter_names(o, d);
  const int32_t K = est.k();
  // Unknowns: the k parameters of every sensor but the reference, in sensor order.
  std::vector<int32_t> slot(S, -1);
  int32_t P = 0;
  for (int32_t s = 0; s < S; ++s)
    if (s != o.reference_sensor) slot[s] = P++ * K;
  const int32_t unknowns = P * K;
  const std::vector<double> sigma = prior_sigmas(o, d);
  Eigen::VectorXd prior(unknowns);
  for (int32_t p = 0; p < P; ++p)
    for (int32_t j = 0; j < K; ++j) prior[p * K + j] = 1.0 / (sigma[j] * sigma[j]);

  // Per observation, once: C⁻¹ (d×d), the two Jacobians, the difference.
  std::vector<Eigen::MatrixXd> Cinv(N), Ja(N), Jb(N);
  std::vector<Eigen::VectorXd> diff(N);
  for (std::size_t i = 0; i < N; ++i) {
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> C(
        obs.covariance.data() + i * d * d, d, d);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(C);
    require(ldlt.info() == Eigen::Success && ldlt.isPositive(),
            "fit_registration: observation " + std::to_string(i), "expected a positive definite covariance");
    Cinv[i] = ldlt.solve(Eigen::MatrixXd::Identity(d, d));
    const std::span<const double> xa(obs.position_a.data() + i * d, d), xb(obs.position_b.data() + i * d, d);
    const std::span<const double> va(obs.velocity_a.data() + i * d, d), vb(obs.velocity_b.data() + i * d, d);
    Ja[i] = registration_jacobian(o, d, sites[obs.sensor_a[i]], xa, va);
    Jb[i] = registration_jacobian(o, d, sites[obs.sensor_b[i]], xb, vb);
    diff[i] =
        Eigen::Map<const Eigen::VectorXd>(xa.data(), d) - Eigen::Map<const Eigen::VectorXd>(xb.data(), d);
  }
  // A_i β = J_a b_a − J_b b_b: the rows touch at most two parameter blocks.
  auto residual = [&](std::size_t i, const Eigen::VectorXd& beta) {
    Eigen::VectorXd r = diff[i];
    const int32_t a = slot[obs.sensor_a[i]], b = slot[obs.sensor_b[i]];
    if (a >= 0) r -= Ja[i] * beta.segment(a, K);
    if (b >= 0) r += Jb[i] * beta.segment(b, K);
    return r;
  };
  // Scatters the d×unknowns A_i as (block, sign, J) pairs.
  auto accumulate = [&](std::size_t i, double w, Eigen::MatrixXd& H, Eigen::VectorXd* g,
                        Eigen::VectorXd* score, const Eigen::VectorXd* r) {
    const int32_t blocks[2] = {slot[obs.sensor_a[i]], slot[obs.sensor_b[i]]};
    const Eigen::MatrixXd* J[2] = {&Ja[i], &Jb[i]};
    const double sign[2] = {1.0, -1.0};
    for (int u = 0; u < 2; ++u) {
      if (blocks[u] < 0) continue;
      const Eigen::MatrixXd JtW = sign[u] * w * J[u]->transpose() * Cinv[i];
      if (g) g->segment(blocks[u], K) += JtW * diff[i];
      if (score) score->segment(blocks[u], K) += JtW * *r;
      for (int v = 0; v < 2; ++v)
        if (blocks[v] >= 0) H.block(blocks[u], blocks[v], K, K) += JtW * (sign[v] * *J[v]);
    }
  };

  Eigen::VectorXd beta = Eigen::VectorXd::Zero(unknowns);
  std::vector<double> weight(N, 1.0);
  Eigen::MatrixXd H;
  for (int32_t it = 0; it < o.iterations; ++it) {
    H = Eigen::MatrixXd(prior.asDiagonal());
    Eigen::VectorXd g = Eigen::VectorXd::Zero(unknowns);
    for (std::size_t i = 0; i < N; ++i) accumulate(i, weight[i], H, &g, nullptr, nullptr);
    beta = H.ldlt().solve(g);
    est.summary.iterations = it + 1;
    bool changed = false;
    for (std::size_t i = 0; i < N; ++i) {  // Huber weights from the new residuals
      const Eigen::VectorXd r = residual(i, beta);
      const double m = std::sqrt(std::max(0.0, r.dot(Cinv[i] * r)));
      const double w = m <= o.huber ? 1.0 : o.huber / m;
      changed = changed || std::abs(w - weight[i]) > 1e-3;
      weight[i] = w;
    }
    if (!changed) break;
  }
  H = Eigen::MatrixXd(prior.asDiagonal());
  for (std::size_t i = 0; i < N; ++i) accumulate(i, weight[i], H, nullptr, nullptr, nullptr);
  const Eigen::MatrixXd Hinv = H.ldlt().solve(Eigen::MatrixXd::Identity(unknowns, unknowns));

  // The sandwich: one score per cluster (pair of tracks), plus the prior as a pseudo-observation.
  std::map<int64_t, Eigen::VectorXd> score;
  Eigen::MatrixXd unused = Eigen::MatrixXd::Zero(unknowns, unknowns);
  double objective = beta.dot(prior.asDiagonal() * beta);
  est.covariance_scale.assign(static_cast<std::size_t>(S) * S, 0.0);
  est.pair_observations.assign(static_cast<std::size_t>(S) * S, 0);
  for (std::size_t i = 0; i < N; ++i) {
    const Eigen::VectorXd r = residual(i, beta);
    const double m2 = r.dot(Cinv[i] * r);
    objective += weight[i] * m2;
    auto [it, inserted] = score.try_emplace(obs.cluster[i], Eigen::VectorXd::Zero(unknowns));
    accumulate(i, weight[i], unused, nullptr, &it->second, &r);
    const std::size_t ab = static_cast<std::size_t>(obs.sensor_a[i]) * S + obs.sensor_b[i],
                      ba = static_cast<std::size_t>(obs.sensor_b[i]) * S + obs.sensor_a[i];
    est.covariance_scale[ab] += m2 / d;
    est.covariance_scale[ba] += m2 / d;
    ++est.pair_observations[ab];
    ++est.pair_observations[ba];
  }
  for (std::size_t q = 0; q < est.covariance_scale.size(); ++q)
    est.covariance_scale[q] = est.pair_observations[q] > 0
                                  ? est.covariance_scale[q] / static_cast<double>(est.pair_observations[q])
                                  : std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd meat(prior.asDiagonal());
  for (const auto& [c, sc] : score) meat += sc * sc.transpose();
  const Eigen::MatrixXd sandwich = Hinv * meat * Hinv;

  est.bias.assign(static_cast<std::size_t>(S) * K, 0.0);
  est.standard_error.assign(static_cast<std::size_t>(S) * K, 0.0);
  est.covariance.assign(static_cast<std::size_t>(S) * K * K, 0.0);
  for (int32_t s = 0; s < S; ++s) {
    if (slot[s] < 0) continue;
    for (int32_t j = 0; j < K; ++j) {
      est.bias[s * K + j] = beta[slot[s] + j];
      for (int32_t l = 0; l < K; ++l) {
        const double m = Hinv(slot[s] + j, slot[s] + l), w = sandwich(slot[s] + j, slot[s] + l);
        // The larger of the two covariances: entrywise on the diagonal, the sandwich's
        // correlation kept off it.
        est.covariance[(static_cast<std::size_t>(s) * K + j) * K + l] = j == l ? std::max(m, w) : w;
      }
    }
    // Off-diagonal entries rescaled to the chosen variances, so the block stays a covariance.
    for (int32_t j = 0; j < K; ++j)
      for (int32_t l = 0; l < K; ++l) {
        if (j == l) continue;
        const double wj = sandwich(slot[s] + j, slot[s] + j), wl = sandwich(slot[s] + l, slot[s] + l);
        const double vj = est.covariance[(static_cast<std::size_t>(s) * K + j) * K + j],
                     vl = est.covariance[(static_cast<std::size_t>(s) * K + l) * K + l];
        double& c = est.covariance[(static_cast<std::size_t>(s) * K + j) * K + l];
        c = wj > 0 && wl > 0 ? c * std::sqrt(vj * vl / (wj * wl)) : 0.0;
      }
    for (int32_t j = 0; j < K; ++j)
      est.standard_error[s * K + j] =
          std::sqrt(est.covariance[(static_cast<std::size_t>(s) * K + j) * K + j]);
  }
  est.summary.observations = N;
  est.summary.clusters = score.size();
  est.summary.objective = objective;
  est.summary.wall_time_s = seconds_since(t0);
  return est;
}

}  // namespace trackassoc
