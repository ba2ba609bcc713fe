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
  const int D = x.dim;
  const int32_t K = x.n_times;
  require(static_cast<int32_t>(x.times.size()) == K, "gain_complements",
          "the aligned tracks of sensor " + std::to_string(x.sensor) + " carry no common times");
  std::vector<Eigen::MatrixXd> F(K), Q(K);
  for (int32_t k = 1; k < K; ++k) cv_transition(D, x.times[k] - x.times[k - 1], sigma_a, F[k], Q[k]);
  std::vector<double> out(x.valid.size() * D * D, 0.0);
  auto unpack = [&](int64_t cell) {
    Eigen::MatrixXd M(D, D);
    const double* packed = x.cov_at(cell);
    for (int i = 0, p = 0; i < D; ++i)
      for (int j = i; j < D; ++j, ++p) M(i, j) = M(j, i) = packed[p];
    return M;
  };
  parallel_for_range(x.n_tracks(), 16, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t t = lo; t < hi; ++t) {
      const AlignedTracks::Span sp = x.span(static_cast<int32_t>(t));
      for (int32_t k = sp.begin; k < sp.end; ++k) {
        const int64_t cell = x.cell(static_cast<int32_t>(t), k);
        Eigen::MatrixXd A = Eigen::MatrixXd::Identity(D, D);
        if (k > sp.begin && x.valid[cell] && x.valid[cell - 1]) {  // cell − 1 is time k − 1
          const Eigen::MatrixXd prior = F[k] * unpack(cell - 1) * F[k].transpose() + Q[k];
          const Eigen::LLT<Eigen::MatrixXd> llt(prior);
          if (llt.info() != Eigen::Success)
            throw InputError("gain_complements: F P Fᵀ + Q is not positive definite for sensor " +
                             std::to_string(x.sensor) + " track " + std::to_string(x.track[t]) +
                             " at common time " + std::to_string(k));
          A = llt.solve(unpack(cell)).transpose();  // A = P(k|k)·P(k|k−1)⁻¹, both symmetric
        }
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) out[cell * D * D + i * D + j] = A(i, j);
      }
    }
  });
  return out;
}

std::vector<double> cross_covariance_series(const AlignedTracks& a, int32_t ia,
                                            std::span<const double> gain_a, const AlignedTracks& b,
                                            int32_t ib, std::span<const double> gain_b, double sigma_a) {
  const int D = a.dim;
  const int32_t K = a.n_times;
  require(b.dim == D && b.n_times == K && a.times.size() == static_cast<std::size_t>(K),
          "cross_covariance_series",
          "the aligned tracks of sensors " + std::to_string(a.sensor) + " and " + std::to_string(b.sensor) +
              " do not share their common times");
  require(ia >= 0 && ia < a.n_tracks() && ib >= 0 && ib < b.n_tracks(), "cross_covariance_series",
          "track row out of range");
  require(gain_a.size() == a.valid.size() * D * D && gain_b.size() == b.valid.size() * D * D,
          "cross_covariance_series", "gain_complements of the wrong size");
  using RowMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  std::vector<double> out(static_cast<std::size_t>(K) * D * D, 0.0);
  Eigen::MatrixXd Pab = Eigen::MatrixXd::Zero(D, D), F, Q;
  bool chained = false;  // both tracks existed at k − 1
  const AlignedTracks::Span both = common_span(a.span(ia), b.span(ib));
  for (int32_t k = both.begin; k < both.end; ++k) {
    const int64_t ca = a.cell(ia, k), cb = b.cell(ib, k);
    if (!a.valid[ca] || !b.valid[cb]) {
      chained = false;
      continue;
    }
    if (chained) {
      cv_transition(D, a.times[k] - a.times[k - 1], sigma_a, F, Q);
      Pab = cross_covariance_step(RowMap(&gain_a[ca * D * D], D, D), RowMap(&gain_b[cb * D * D], D, D), F, Q,
                                  Pab);
    } else {
      Pab.setZero();
    }
    chained = true;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) out[(static_cast<std::size_t>(k) * D + i) * D + j] = Pab(i, j);
  }
  return out;
}

}  // namespace trackassoc
