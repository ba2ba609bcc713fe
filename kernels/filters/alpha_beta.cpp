#include "kernels/filters/alpha_beta.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

void AlphaBetaOptions::validate() const {
  const std::string w = "AlphaBetaOptions.";
  if (gains == AlphaBetaGainMode::kFixed) {
    require(std::isfinite(alpha) && alpha > 0.0 && alpha < 2.0, w + "alpha",
            "expected 0 < alpha < 2, got " + std::to_string(alpha));
    require(std::isfinite(beta) && beta > 0.0 && beta < 4.0 - 2.0 * alpha, w + "beta",
            "expected 0 < beta < 4 - 2*alpha = " + std::to_string(4.0 - 2.0 * alpha) + ", got " +
                std::to_string(beta));
  } else {
    require(std::isfinite(process_noise) && process_noise > 0.0, w + "process_noise",
            "expected a finite value > 0, got " + std::to_string(process_noise));
    require(std::isfinite(measurement_noise) && measurement_noise > 0.0, w + "measurement_noise",
            "expected a finite value > 0, got " + std::to_string(measurement_noise));
  }
  require(grain > 0, w + "grain", "expected > 0");
}

double tracking_index(double process_noise, double measurement_noise, double step) {
  return process_noise * step * step / measurement_noise;
}

AlphaBetaGains kalata_gains(double lambda) {
  // Kalata 1984 Eq. 27–28.
  const double r = std::sqrt(lambda * lambda + 8.0 * lambda);
  AlphaBetaGains g;
  g.alpha = -(lambda * lambda + 8.0 * lambda - (lambda + 4.0) * r) / 8.0;
  g.beta = (lambda * lambda + 4.0 * lambda - lambda * r) / 4.0;
  return g;
}

AlphaBetaGains expanding_memory_gains(int64_t n) {
  const double m = static_cast<double>(n);
  return {2.0 * (2.0 * m + 1.0) / ((m + 2.0) * (m + 1.0)), 6.0 / ((m + 2.0) * (m + 1.0))};
}

AlphaBetaGains alpha_beta_gains(const AlphaBetaOptions& o, double step, double measurement_noise) {
  if (o.gains == AlphaBetaGainMode::kFixed) return {o.alpha, o.beta};
  return kalata_gains(tracking_index(o.process_noise, measurement_noise, step));
}

AlphaBetaGains alpha_beta_gains(const AlphaBetaOptions& o, double step) {
  return alpha_beta_gains(o, step, o.measurement_noise);
}

std::array<double, 3> alpha_beta_steady_covariance(AlphaBetaGains g, double T, double sw, double sv) {
  require(T > 0.0 && std::isfinite(T), "alpha_beta_steady_covariance.step", "expected > 0");
  require(g.alpha > 0.0 && g.alpha < 2.0 && g.beta > 0.0 && g.beta < 4.0 - 2.0 * g.alpha,
          "alpha_beta_steady_covariance.gains", "not stable (need 0 < alpha < 2, 0 < beta < 4 - 2 alpha)");
  // P = A P Aᵀ + W with A = (I − K H) F, W = (I − K H) Q (I − K H)ᵀ + K σ_v² Kᵀ. Unknowns
  // (pp, pv, vv) of the symmetric P: a 3×3 linear system.
  Eigen::Matrix2d F;
  F << 1.0, T, 0.0, 1.0;
  Eigen::Vector2d K(g.alpha, g.beta / T);
  Eigen::Matrix2d IKH = Eigen::Matrix2d::Identity();
  IKH(0, 0) -= K(0);
  IKH(1, 0) -= K(1);
  Eigen::Matrix2d Q;
  Q << T * T * T * T / 4.0, T * T * T / 2.0, T * T * T / 2.0, T * T;
  Q *= sw * sw;
  const Eigen::Matrix2d A = IKH * F;
  const Eigen::Matrix2d W = IKH * Q * IKH.transpose() + K * K.transpose() * (sv * sv);
  // Column j of the map P ↦ A P Aᵀ on the basis E_pp, E_pv (symmetric), E_vv.
  const Eigen::Matrix2d E[3] = {(Eigen::Matrix2d() << 1, 0, 0, 0).finished(),
                                (Eigen::Matrix2d() << 0, 1, 1, 0).finished(),
                                (Eigen::Matrix2d() << 0, 0, 0, 1).finished()};
  Eigen::Matrix3d M;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Matrix2d X = A * E[j] * A.transpose();
    M(0, j) = X(0, 0);
    M(1, j) = X(0, 1);
    M(2, j) = X(1, 1);
  }
  const Eigen::Vector3d w(W(0, 0), W(0, 1), W(1, 1));
  const Eigen::Vector3d p = (Eigen::Matrix3d::Identity() - M).partialPivLu().solve(w);
  return {p(0), p(1), p(2)};
}

AlphaBetaBank::AlphaBetaBank(int spatial_dim, std::size_t n, const AlphaBetaOptions& options)
    : spatial_dim_(spatial_dim), options_(options) {
  require(spatial_dim == 2 || spatial_dim == 3, "AlphaBetaBank.spatial_dim",
          "expected 2 or 3, got " + std::to_string(spatial_dim));
  options_.validate();
  for (int a = 0; a < spatial_dim_; ++a) {
    position[a].assign(n, 0.0);
    velocity[a].assign(n, 0.0);
  }
  alpha.assign(n, 0.0);
  beta.assign(n, 0.0);
  step.assign(n, 0.0);
  measurements.assign(n, 0);
  measurement_noise.assign(n, options_.measurement_noise);
}

void AlphaBetaBank::initialise(std::size_t i, std::span<const double> pos, std::span<const double> vel,
                               int64_t count) {
  require(count >= 0, "AlphaBetaBank.initialise", "measurements must be >= 0");
  require(i < size(), "AlphaBetaBank.initialise", "track index out of range");
  require(pos.size() == static_cast<std::size_t>(spatial_dim_) && vel.size() == pos.size(),
          "AlphaBetaBank.initialise", "expected spatial_dim position and velocity entries");
  for (int a = 0; a < spatial_dim_; ++a) {
    position[a][i] = pos[a];
    velocity[a][i] = vel[a];
  }
  alpha[i] = beta[i] = step[i] = 0.0;
  measurements[i] = count;
}

std::size_t AlphaBetaBank::add_track(std::span<const double> pos, std::span<const double> vel,
                                     int64_t count) {
  for (int a = 0; a < spatial_dim_; ++a) {
    position[a].push_back(0.0);
    velocity[a].push_back(0.0);
  }
  alpha.push_back(0.0);
  beta.push_back(0.0);
  step.push_back(0.0);
  measurements.push_back(0);
  measurement_noise.push_back(options_.measurement_noise);
  initialise(size() - 1, pos, vel, count);
  return size() - 1;
}

// Element kernels: the one place the α-β equations are written.
namespace {

inline void predict_element(double* p, const double* v, std::size_t i, double T) { p[i] += T * v[i]; }

// The gains of one update: steady (a, b) or, during the expanding-memory start, the
// least-squares ones (Brookner §1.2.6).
inline AlphaBetaGains effective_gains(double a, double b, int64_t n, bool expanding) {
  if (expanding) {
    const AlphaBetaGains g = expanding_memory_gains(n);
    if (g.alpha > a) return g;
  }
  return {a, b};
}

inline void update_element(double* p, double* v, std::size_t i, double z, double a, double b_over_t) {
  const double r = z - p[i];
  p[i] += a * r;
  v[i] += b_over_t * r;
}

}  // namespace

void AlphaBetaBank::predict(double T) {
  require(T >= 0.0 && std::isfinite(T), "AlphaBetaBank.predict", "expected a finite step >= 0");
  if (T == 0.0) return;
  const AlphaBetaGains g0 = alpha_beta_gains(options_, T);
  parallel_for_range(size(), options_.grain, [&](std::size_t b, std::size_t e) {
    for (int a = 0; a < spatial_dim_; ++a) {
      double* p = position[a].data();
      const double* v = velocity[a].data();
      for (std::size_t i = b; i < e; ++i) predict_element(p, v, i, T);
    }
    for (std::size_t i = b; i < e; ++i) {
      const AlphaBetaGains g = measurement_noise[i] == options_.measurement_noise
                                   ? g0
                                   : alpha_beta_gains(options_, T, measurement_noise[i]);
      alpha[i] = g.alpha;
      beta[i] = g.beta;
      step[i] = T;
    }
  });
}

void AlphaBetaBank::predict(std::span<const double> steps) {
  require(steps.size() == size(), "AlphaBetaBank.predict", "expected one step per track");
  for (double T : steps)
    require(T >= 0.0 && std::isfinite(T), "AlphaBetaBank.predict", "expected finite steps >= 0");
  parallel_for_range(size(), options_.grain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) predict_track(i, steps[i]);
  });
}

void AlphaBetaBank::predict_track(std::size_t i, double T) {
  if (!(T > 0.0)) return;  // T = 0: keep the previous gains and step
  for (int a = 0; a < spatial_dim_; ++a) predict_element(position[a].data(), velocity[a].data(), i, T);
  const AlphaBetaGains g = alpha_beta_gains(options_, T, measurement_noise[i]);
  alpha[i] = g.alpha;
  beta[i] = g.beta;
  step[i] = T;
}

void AlphaBetaBank::update(std::span<const std::span<const double>> z, std::span<const uint8_t> detected) {
  require(z.size() == static_cast<std::size_t>(spatial_dim_), "AlphaBetaBank.update",
          "expected spatial_dim measurement columns");
  for (const auto& c : z)
    require(c.size() == size(), "AlphaBetaBank.update", "expected one measurement per track");
  require(detected.size() == size(), "AlphaBetaBank.update", "expected one detected flag per track");
  const bool expanding = options_.expanding_memory_start;
  parallel_for_range(size(), options_.grain, [&](std::size_t b, std::size_t e) {
    // Chunks of kChunk tracks: the gains of the chunk first (branchy), then one branch-free,
    // vectorised loop per axis. Undetected tracks and tracks never predicted get zero gains.
    constexpr std::size_t kChunk = 256;
    double ga[kChunk], gb[kChunk];
    for (std::size_t c0 = b; c0 < e; c0 += kChunk) {
      const std::size_t m = std::min(kChunk, e - c0);
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t i = c0 + k;
        const bool on = detected[i] && step[i] > 0.0;
        const AlphaBetaGains g = effective_gains(alpha[i], beta[i], measurements[i], expanding);
        ga[k] = on ? g.alpha : 0.0;
        gb[k] = on ? g.beta / step[i] : 0.0;
        measurements[i] += on ? 1 : 0;
      }
      for (int a = 0; a < spatial_dim_; ++a) {
        double* p = position[a].data() + c0;
        double* v = velocity[a].data() + c0;
        const double* za = z[a].data() + c0;
        // A zero gain must leave the state exactly unchanged, whatever z holds (NaN for a miss).
        for (std::size_t k = 0; k < m; ++k)
          update_element(p, v, k, ga[k] != 0.0 ? za[k] : p[k], ga[k], gb[k]);
      }
    }
  });
}

AlphaBetaGains AlphaBetaBank::next_update_gains(std::size_t i) const {
  if (!(step[i] > 0.0)) return {};
  return effective_gains(alpha[i], beta[i], measurements[i], options_.expanding_memory_start);
}

void AlphaBetaBank::update_track(std::size_t i, std::span<const double> z) {
  if (!(step[i] > 0.0)) return;
  const AlphaBetaGains g =
      effective_gains(alpha[i], beta[i], measurements[i], options_.expanding_memory_start);
  const double bt = g.beta / step[i];
  for (int a = 0; a < spatial_dim_; ++a)
    update_element(position[a].data(), velocity[a].data(), i, z[a], g.alpha, bt);
  ++measurements[i];
}

}  // namespace trackassoc
