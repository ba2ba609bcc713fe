// The per-track Kalman filter written the obvious way with Eigen dynamic matrices: one object per
// track, textbook formulas (Bar-Shalom, Li, Kirubarajan 2001, §5.2.3) with F = F1 ⊗ I_d and
// Q = Q1 ⊗ I_d built from kalman_bank.hpp's kinematic_transition / kinematic_process_noise.
// It is the reference the batched bank is tested against and the naive baseline of
// bench/bench_filters.cpp. Not used on any production path.
#pragma once

#include <Eigen/Dense>

#include "kernels/filters/kalman_bank.hpp"

namespace trackassoc {

class ReferenceKalmanFilter {
 public:
  ReferenceKalmanFilter(int spatial_dim, int order, double sigma)
      : d_(spatial_dim), n_(order), sigma_(sigma) {
    x = Eigen::VectorXd::Zero(d_ * n_);
    P = Eigen::MatrixXd::Identity(d_ * n_, d_ * n_);
  }
  // Kronecker product A ⊗ I_d in the derivative-block ordering of the bank.
  Eigen::MatrixXd expand(const Eigen::MatrixXd& A) const {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(d_ * n_, d_ * n_);
    for (int i = 0; i < n_; ++i)
      for (int j = 0; j < n_; ++j)
        M.block(i * d_, j * d_, d_, d_) = A(i, j) * Eigen::MatrixXd::Identity(d_, d_);
    return M;
  }
  void predict(double dt) {
    const Eigen::MatrixXd F = expand(kinematic_transition(n_, dt));
    const Eigen::MatrixXd Q = expand(kinematic_process_noise(n_, dt, sigma_));
    x = F * x;
    P = F * P * F.transpose() + Q;
  }
  // Returns the normalised innovation squared.
  double update(const Eigen::VectorXd& z, const Eigen::MatrixXd& R) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(d_, d_ * n_);
    H.leftCols(d_).setIdentity();
    const Eigen::VectorXd nu = z - H * x;
    const Eigen::MatrixXd S = H * P * H.transpose() + R;
    const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
    x += K * nu;
    P -= K * S * K.transpose();
    return nu.dot(S.inverse() * nu);
  }
  Eigen::VectorXd x;
  Eigen::MatrixXd P;

 private:
  int d_, n_;
  double sigma_;
};

}  // namespace trackassoc
