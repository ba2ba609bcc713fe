// cross_covariance_series (kernels/statistics/cross_covariance.hpp), the Bar-Shalom–Campo
// recursion that track fusion reads, is the one the correlated statistic uses: the scan terms of
// scan_terms(--common-process-noise) equal dᵀ(P_a + P_b − P_ab − P_abᵀ)⁻¹d with its P_ab, and
// P_ab is 0 at the first common time and follows A_a[F P_ab Fᵀ + Q]A_bᵀ after it.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cross_covariance.hpp"

namespace trackassoc {
namespace {

TEST(CrossCovarianceSeries, IsTheRecursionOfTheCorrelatedStatistic) {
  // Two synchronous CV-like tracks of one target with shrinking covariances (as a filter settles).
  TrackTable t;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n;
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k < 12; ++k) {
      Eigen::VectorXd x(4);
      x << 100 * k + 20 * n(rng), 5 * k + 20 * n(rng), 100 + n(rng), 5 + n(rng);
      Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
      const double shrink = 1.0 + 4.0 / (k + 1);
      P(0, 0) = P(1, 1) = (400.0 + 100 * s) * shrink;
      P(0, 2) = P(2, 0) = P(1, 3) = P(3, 1) = 30.0 * shrink;
      P(2, 2) = P(3, 3) = 9.0 * shrink;
      t.push_back(s, 7, 2.0 * k, x, P, 0);
    }
  std::vector<double> times;
  for (int k = 0; k < 12; ++k) times.push_back(2.0 * k);
  AlignmentOptions align;
  align.method = AlignmentMethod::kForward;
  const AlignedTracks a = align_tracks(t, 0, times, align), b = align_tracks(t, 1, times, align);
  const double sigma = 1.5;
  const std::vector<double> ga = gain_complements(a, sigma), gb = gain_complements(b, sigma);
  const std::vector<double> series = cross_covariance_series(a, 0, ga, b, 0, gb, sigma);
  StatisticOptions opt;
  opt.common_process_noise = sigma;
  const std::vector<double> terms = scan_terms(a, 0, b, 0, opt);
  using RowMat = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;
  auto unpack = [](const std::vector<double>& packed, std::size_t off) {
    Eigen::Matrix4d M;
    for (int i = 0, p = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j, ++p) M(i, j) = M(j, i) = packed[off + p];
    return M;
  };
  Eigen::Matrix4d expected = Eigen::Matrix4d::Zero();
  for (int k = 0; k < 12; ++k) {
    const Eigen::Matrix4d Pab = Eigen::Map<const RowMat>(&series[k * 16]);
    if (k > 0) {
      Eigen::MatrixXd F, Q;
      cv_transition(4, 2.0, sigma, F, Q);
      expected = Eigen::Map<const RowMat>(&ga[k * 16]) * (F * expected * F.transpose() + Q) *
                 Eigen::Map<const RowMat>(&gb[k * 16]).transpose();
    }
    EXPECT_TRUE(Pab.isApprox(expected, 1e-12) || (k == 0 && Pab.isZero())) << k;
    const Eigen::Matrix4d C = unpack(a.cov, k * 10) + unpack(b.cov, k * 10) - Pab - Pab.transpose();
    Eigen::Vector4d d;
    for (int c = 0; c < 4; ++c) d[c] = a.state[k * 4 + c] - b.state[k * 4 + c];
    EXPECT_NEAR(terms[k], d.dot(C.ldlt().solve(d)), 1e-9 * (1 + terms[k])) << k;
  }
  EXPECT_GT(Eigen::Map<const RowMat>(&series[11 * 16]).norm(), 0.0);  // the recursion did build up
}

}  // namespace
}  // namespace trackassoc
