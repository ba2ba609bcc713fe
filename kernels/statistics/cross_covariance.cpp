// Bar-Shalom–Campo cross-covariance from common process noise: see the header.
#include "kernels/statistics/cross_covariance.hpp"

#include <Eigen/Cholesky>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

void cv_transition(int dim, double dt, double sigma_a, Eigen::MatrixXd& F, Eigen::MatrixXd& Q) {
  const int m = dim / 2;
  const double q = sigma_a * sigma_a;
  F = Eigen::MatrixXd::Identity(dim, dim);
  Q = Eigen::MatrixXd::Zero(dim, dim);
  for (int c = 0; c < m; ++c) {
    F(c, m + c) = dt;
    Q(c, c) = q * dt * dt * dt * dt / 4.0;
    Q(c, m + c) = Q(m + c, c) = q * dt * dt * dt / 2.0;
    Q(m + c, m + c) = q * dt * dt;
  }
}

std::vector<double> gain_complements(const AlignedTracks& x, double sigma_a) {
  const int D = x.dim, P = packed_size(D);
  const int32_t K = x.n_times;
  require(static_cast<int32_t>(x.times.size()) == K, "gain_complements",
          "the aligned tracks of sensor " + std::to_string(x.sensor) + " carry no common times");
  std::vector<Eigen::MatrixXd> F(K), Q(K);
  for (int32_t k = 1; k < K; ++k) cv_transition(D, x.times[k] - x.times[k - 1], sigma_a, F[k], Q[k]);
  std::vector<double> out(x.valid.size() * D * D, 0.0);
  auto unpack = [&](std::size_t cell) {
    Eigen::MatrixXd M(D, D);
    for (int i = 0, p = 0; i < D; ++i)
      for (int j = i; j < D; ++j, ++p) M(i, j) = M(j, i) = x.cov[cell * P + p];
    return M;
  };
  parallel_for_range(x.valid.size(), 64, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t cell = lo; cell < hi; ++cell) {
      const int32_t k = static_cast<int32_t>(cell % K);
      Eigen::MatrixXd A = Eigen::MatrixXd::Identity(D, D);
      if (k > 0 && x.valid[cell] && x.valid[cell - 1]) {
        const Eigen::MatrixXd prior = F[k] * unpack(cell - 1) * F[k].transpose() + Q[k];
        const Eigen::LLT<Eigen::MatrixXd> llt(prior);
        if (llt.info() != Eigen::Success)
          throw InputError("gain_complements: F P Fᵀ + Q is not positive definite for sensor " +
                           std::to_string(x.sensor) + " track " + std::to_string(x.track[cell / K]) +
                           " at common time " + std::to_string(k));
        A = llt.solve(unpack(cell)).transpose();  // A = P(k|k)·P(k|k−1)⁻¹, both symmetric
      }
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) out[cell * D * D + i * D + j] = A(i, j);
    }
  });
  return out;
}

}  // namespace trackassoc
