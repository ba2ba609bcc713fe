// Synthetic recorded track sets for the sparse-path tests and benchmarks: n targets moving at
// constant velocity in a box, S sensors with their own periods and offsets, each local track =
// truth + Gaussian error drawn from the covariance it reports (so the statistic's model holds
// exactly). Track numbers are shuffled per sensor; a sensor sees a target with probability
// p_seen. All randomness from CounterRng (seed, stream).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <numeric>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/random.hpp"
#include "kernels/types.hpp"

namespace trackassoc::testing {

struct SyntheticSpec {
  int32_t targets = 50;
  int32_t sensors = 3;
  bool three_d = true;
  double box = 20000.0;       // side of the area [m]
  double speed = 200.0;       // [m/s]
  double duration = 20.0;     // [s]
  double sigma_pos = 50.0;    // position error σ [m]
  double sigma_vel = 5.0;     // velocity error σ [m/s]
  double p_seen = 1.0;
  bool formation = false;     // all targets share one velocity (dense crossing-free clusters)
  std::vector<double> periods{1.0, 2.0, 1.5, 2.5};
  std::vector<double> offsets{0.0, 0.3, 0.7, 0.2};
  uint64_t seed = 1;
};

inline TrackFile synthetic_track_file(const SyntheticSpec& spec) {
  const StateLayout layout = spec.three_d ? StateLayout::kXYZ_VXVYVZ : StateLayout::kXY_VXVY;
  const int D = state_dim(layout), m = D / 2;
  TrackFile file;
  file.tracks.reset(layout);
  std::vector<Eigen::VectorXd> x0(spec.targets, Eigen::VectorXd(D));
  CounterRng trng(spec.seed, 0, 1000);
  Eigen::VectorXd v(m);
  for (auto& x : x0) {
    for (int c = 0; c < m; ++c) x[c] = trng.uniform(0.0, spec.box);
    if (!spec.formation || &x == &x0.front()) {
      for (int c = 0; c < m; ++c) v[c] = trng.normal();
      v *= spec.speed / v.norm();
    }
    x.tail(m) = v;
  }
  for (int32_t s = 0; s < spec.sensors; ++s) {
    Sensor sensor;
    sensor.id = s + 1;
    sensor.period = spec.periods[s % spec.periods.size()];
    sensor.offset = spec.offsets[s % spec.offsets.size()];
    file.sensors.push_back(sensor);
    CounterRng rng(spec.seed, 1, static_cast<uint64_t>(s));
    std::vector<int32_t> seen, number;
    for (int32_t g = 0; g < spec.targets; ++g)
      if (rng.uniform() < spec.p_seen) seen.push_back(g);
    number.resize(seen.size());
    std::iota(number.begin(), number.end(), 0);
    rng.shuffle(std::span<int32_t>(number));
    for (std::size_t q = 0; q < seen.size(); ++q) {
      const int32_t g = seen[q];
      CounterRng e(spec.seed, 2 + static_cast<uint64_t>(s), static_cast<uint64_t>(g));
      // Per-track covariance: diagonal, scaled by a factor in [0.5, 2].
      const double scale = e.uniform(0.5, 2.0);
      Eigen::MatrixXd P = Eigen::MatrixXd::Zero(D, D);
      for (int c = 0; c < m; ++c) {
        P(c, c) = scale * spec.sigma_pos * spec.sigma_pos;
        P(m + c, m + c) = scale * spec.sigma_vel * spec.sigma_vel;
      }
      const Eigen::MatrixXd L = P.llt().matrixL();
      for (double t = sensor.offset; t <= spec.duration + 1e-9; t += sensor.period) {
        Eigen::VectorXd x = x0[g];
        x.head(m) += t * x0[g].tail(m);
        Eigen::VectorXd z(D);
        for (int c = 0; c < D; ++c) z[c] = e.normal();
        file.tracks.push_back(sensor.id, number[q], t, x + L * z, P, g);
      }
    }
  }
  return file;
}

}  // namespace trackassoc::testing
