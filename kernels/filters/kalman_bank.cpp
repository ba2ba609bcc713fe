#include "kernels/filters/kalman_bank.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/filters/kalman_block.hpp"

namespace trackassoc {

static_assert(kBankLanes == block::W);

KinematicBank::KinematicBank(int spatial_dim, int order, std::size_t tracks)
    : d_(spatial_dim), n_(order), size_(tracks) {
  require(spatial_dim == 2 || spatial_dim == 3, "KinematicBank.spatial_dim",
          "expected 2 or 3, got " + std::to_string(spatial_dim));
  require(order == 2 || order == 3, "KinematicBank.order",
          "expected 2 (CV) or 3 (CA), got " + std::to_string(order));
  data_.assign(num_blocks() * block_stride(), 0.0);
  for (std::size_t b = 0; b < num_blocks(); ++b)
    for (int r = 0; r < dim(); ++r)
      for (int l = 0; l < kBankLanes; ++l) block(b)[(dim() + packed(r, r)) * kBankLanes + l] = 1.0;
}

Eigen::VectorXd KinematicBank::state_vector(std::size_t i) const {
  Eigen::VectorXd x(dim());
  for (int c = 0; c < dim(); ++c) x[c] = state(i, c);
  return x;
}

Eigen::MatrixXd KinematicBank::covariance(std::size_t i) const {
  Eigen::MatrixXd P(dim(), dim());
  for (int r = 0; r < dim(); ++r)
    for (int c = r; c < dim(); ++c) P(r, c) = P(c, r) = cov(i, r, c);
  return P;
}

void KinematicBank::set(std::size_t i, const Eigen::VectorXd& x, const Eigen::MatrixXd& P) {
  for (int c = 0; c < dim(); ++c) set_state(i, c, x[c]);
  for (int r = 0; r < dim(); ++r)
    for (int c = r; c < dim(); ++c) set_cov(i, r, c, P(r, c));
}

void KalmanOptions::validate() const {
  require(model == KalmanModel::kConstantVelocity || model == KalmanModel::kConstantAcceleration,
          "KalmanOptions.model", "expected CV or CA");
  require(std::isfinite(process_noise) && process_noise >= 0.0, "KalmanOptions.process_noise",
          "expected a finite σ ≥ 0 [m/s²], got " + std::to_string(process_noise));
  require(grain_blocks >= 1, "KalmanOptions.grain_blocks", "expected ≥ 1");
}

Eigen::MatrixXd kinematic_transition(int order, double dt) {
  Eigen::MatrixXd F = Eigen::MatrixXd::Identity(order, order);
  F(0, 1) = dt;
  if (order == 3) {
    F(0, 2) = 0.5 * dt * dt;
    F(1, 2) = dt;
  }
  return F;
}

Eigen::MatrixXd kinematic_process_noise(int order, double dt, double sigma) {
  Eigen::VectorXd g(order);
  g[0] = 0.5 * dt * dt;
  g[1] = dt;
  if (order == 3) g[2] = 1.0;
  return sigma * sigma * g * g.transpose();
}

void two_point_initialise(KinematicBank& bank, std::size_t i, const Eigen::VectorXd& z1,
                          const Eigen::MatrixXd& R1, const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2,
                          double dt, double accel_variance) {
  const int d = bank.spatial_dim(), D = bank.dim();
  require(dt > 0.0, "two_point_initialise.dt", "expected the two plots at distinct times");
  Eigen::VectorXd x = Eigen::VectorXd::Zero(D);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(D, D);
  x.head(d) = z2;
  x.segment(d, d) = (z2 - z1) / dt;
  P.topLeftCorner(d, d) = R2;
  P.block(0, d, d, d) = R2 / dt;
  P.block(d, 0, d, d) = R2 / dt;
  P.block(d, d, d, d) = (R1 + R2) / (dt * dt);
  if (bank.order() == 3) P.bottomRightCorner(d, d) = accel_variance * Eigen::MatrixXd::Identity(d, d);
  bank.set(i, x, P);
}

namespace block {

void check_scan(const PositionScan& scan, const InnovationOutput& out, std::size_t n, int d,
                const char* where) {
  const std::string w(where);
  for (int a = 0; a < d; ++a)
    require(scan.z[a].size() == n, w + ".z", "expected " + std::to_string(n) + " entries per component");
  for (int k = 0; k < packed(d); ++k)
    require(scan.R[k].size() == n, w + ".R", "expected " + std::to_string(n) + " entries per component");
  require(scan.detected.empty() || scan.detected.size() == n, w + ".detected",
          "expected empty or one flag per track");
  require(out.nis.empty() || out.nis.size() == n, w + ".nis", "expected empty or one entry per track");
  require(out.log_likelihood.empty() || out.log_likelihood.size() == n, w + ".log_likelihood",
          "expected empty or one entry per track");
}

}  // namespace block

namespace {

template <int d, int n>
void kalman_blocks(KinematicBank& bank, double dt, const PositionScan& scan, double sigma,
                   const InnovationOutput& out, std::size_t begin, std::size_t end) {
  block::LaneModel<d, n> model;
  const Eigen::MatrixXd F1 = kinematic_transition(n, dt);
  const Eigen::MatrixXd Q1 = kinematic_process_noise(n, dt, sigma);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < block::W; ++l) model.F1[i][j][l] = F1(i, j);
  for (int a = 0; a < d; ++a)
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j)
        for (int l = 0; l < block::W; ++l) model.Q1[a][block::pidx(n, i, j)][l] = Q1(i, j);
  const bool want = !out.nis.empty() || !out.log_likelihood.empty();
  block::LaneMeasurement<d> m;
  block::LaneInnovation v;
  for (std::size_t b = begin; b < end; ++b) {
    double* blk = bank.block(b);
    if (dt != 0.0) block::predict<d, n>(blk, model);
    block::load_measurement<d>(scan, b, bank.size(), m);
    block::update<d, n>(blk, m, want ? &v : nullptr);
    if (want) block::store_innovation(out, b, bank.size(), v);
  }
}

template <int d, int n>
void kalman_parallel(KinematicBank& bank, double dt, const PositionScan& scan, const KalmanOptions& o,
                     const InnovationOutput& out) {
  parallel_for_range(bank.num_blocks(), o.grain_blocks, [&](std::size_t b, std::size_t e) {
    kalman_blocks<d, n>(bank, dt, scan, o.process_noise, out, b, e);
  });
}

}  // namespace

FilterStepSummary kinematic_bank_update(KinematicBank& bank, const PositionScan& scan, InnovationOutput out,
                                        std::size_t grain_blocks) {
  block::check_scan(scan, out, bank.size(), bank.spatial_dim(), "kinematic_bank_update.scan");
  const bool want = !out.nis.empty() || !out.log_likelihood.empty();
  block::dispatch(bank.spatial_dim(), bank.order(), [&](auto dc, auto nc) {
    constexpr int d = decltype(dc)::value, n = decltype(nc)::value;
    parallel_for_range(bank.num_blocks(), std::max<std::size_t>(1, grain_blocks),
                       [&](std::size_t b0, std::size_t b1) {
                         block::LaneMeasurement<d> m;
                         block::LaneInnovation v;
                         for (std::size_t b = b0; b < b1; ++b) {
                           block::load_measurement<d>(scan, b, bank.size(), m);
                           block::update<d, n>(bank.block(b), m, want ? &v : nullptr);
                           if (want) block::store_innovation(out, b, bank.size(), v);
                         }
                       });
  });
  FilterStepSummary s;
  s.tracks = bank.size();
  s.updated = scan.detected.empty() ? bank.size() : 0;
  for (uint8_t f : scan.detected) s.updated += f != 0;
  return s;
}

FilterStepSummary kalman_bank_step(KinematicBank& bank, double dt, const PositionScan& scan,
                                   const KalmanOptions& options, InnovationOutput out) {
  options.validate();
  require(std::isfinite(dt) && dt >= 0.0, "kalman_bank_step.dt",
          "expected a finite scan interval ≥ 0, got " + std::to_string(dt));
  require(bank.order() == static_cast<int>(options.model), "kalman_bank_step.model",
          "the bank's order does not match KalmanOptions.model");
  block::check_scan(scan, out, bank.size(), bank.spatial_dim(), "kalman_bank_step.scan");
  const int key = bank.spatial_dim() * 10 + bank.order();
  switch (key) {
    case 22:
      kalman_parallel<2, 2>(bank, dt, scan, options, out);
      break;
    case 23:
      kalman_parallel<2, 3>(bank, dt, scan, options, out);
      break;
    case 32:
      kalman_parallel<3, 2>(bank, dt, scan, options, out);
      break;
    default:
      kalman_parallel<3, 3>(bank, dt, scan, options, out);
      break;
  }
  FilterStepSummary s;
  s.tracks = bank.size();
  if (scan.detected.empty()) {
    s.updated = bank.size();
  } else {
    for (uint8_t f : scan.detected) s.updated += f != 0;
  }
  return s;
}

}  // namespace trackassoc
