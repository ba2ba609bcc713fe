// Track-to-track fusion rules (kernels/fusion/track_fusion.hpp) against hand-computed closed forms,
// the general BLUE, and brute-force searches over the covariance-intersection weights.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "kernels/core/error.hpp"
#include "kernels/fusion/track_fusion.hpp"

namespace trackassoc {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

VectorXd vec(std::initializer_list<double> v) {
  VectorXd x(v.size());
  int i = 0;
  for (double e : v) x[i++] = e;
  return x;
}
MatrixXd diag(std::initializer_list<double> v) { return vec(v).asDiagonal(); }
MatrixXd scalar(double v) { return MatrixXd::Constant(1, 1, v); }

MatrixXd random_spd(int d, std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  MatrixXd A(d, d);
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) A(i, j) = n(rng);
  return A * A.transpose() + 0.1 * MatrixXd::Identity(d, d);
}

TEST(NaiveFusion, OneDimensionalClosedForm) {
  // P = (1/4 + 1/1)⁻¹ = 0.8, x = 0.8·(0/4 + 5/1) = 4.
  const VectorXd x[] = {vec({0.0}), vec({5.0})};
  const MatrixXd P[] = {scalar(4.0), scalar(1.0)};
  const FusedEstimate f = fuse_naive(x, P);
  EXPECT_NEAR(f.P(0, 0), 0.8, 1e-12);
  EXPECT_NEAR(f.x[0], 4.0, 1e-12);
}

TEST(NaiveFusion, TwoDimensionalClosedForm) {
  // Per axis: P = (1/1 + 1/4)⁻¹ = 0.8; x = 0.8·(0/1 + 10/4) = 2, y = 0.8·(0/4 + 10/1) = 8.
  const VectorXd x[] = {vec({0, 0}), vec({10, 10})};
  const MatrixXd P[] = {diag({1, 4}), diag({4, 1})};
  const FusedEstimate f = fuse_naive(x, P);
  EXPECT_TRUE(f.P.isApprox(diag({0.8, 0.8}), 1e-12));
  EXPECT_NEAR(f.x[0], 2.0, 1e-12);
  EXPECT_NEAR(f.x[1], 8.0, 1e-12);
}

TEST(BarShalomCampo, OneDimensionalClosedForm) {
  // P1 = 4, P2 = 1, P12 = 0.5: weight of x2 = (P1 − P12)/(P1 + P2 − 2 P12) = 3.5/4,
  // P = (P1 P2 − P12²)/(P1 + P2 − 2 P12) = 3.75/4 = 0.9375.
  const FusedEstimate f =
      fuse_bar_shalom_campo(vec({0.0}), scalar(4.0), vec({5.0}), scalar(1.0), scalar(0.5));
  EXPECT_NEAR(f.x[0], 5.0 * 3.5 / 4.0, 1e-12);
  EXPECT_NEAR(f.P(0, 0), 0.9375, 1e-12);
}

TEST(BarShalomCampo, TwoDimensionalDiagonalClosedForm) {
  // Axis x as above; axis y: P1 = 9, P2 = 1, P12 = 1 → weight (9 − 1)/(9 + 1 − 2) = 1, P = (9 − 1)/8 = 1.
  const FusedEstimate f =
      fuse_bar_shalom_campo(vec({0, 0}), diag({4, 9}), vec({5, 3}), diag({1, 1}), diag({0.5, 1}));
  EXPECT_NEAR(f.x[0], 4.375, 1e-12);
  EXPECT_NEAR(f.x[1], 3.0, 1e-12);
  EXPECT_TRUE(f.P.isApprox(diag({0.9375, 1.0}), 1e-12));
}

TEST(BarShalomCampo, ZeroCrossCovarianceIsNaive) {
  std::mt19937_64 rng(3);
  const MatrixXd P[] = {random_spd(4, rng), random_spd(4, rng)};
  const VectorXd x[] = {VectorXd::Random(4), VectorXd::Random(4)};
  const FusedEstimate b = fuse_bar_shalom_campo(x[0], P[0], x[1], P[1], MatrixXd::Zero(4, 4));
  const FusedEstimate n = fuse_naive(x, P);
  EXPECT_TRUE(b.P.isApprox(n.P, 1e-10));
  EXPECT_TRUE(b.x.isApprox(n.x, 1e-10));
}

TEST(BarShalomCampo, EqualsTheBlueOfTheJointCovariance) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const MatrixXd joint = random_spd(8, rng);  // any SPD joint covariance of two 4-D errors
    const VectorXd x[] = {VectorXd::Random(4), VectorXd::Random(4)};
    const FusedEstimate b = fuse_bar_shalom_campo(x[0], joint.block(0, 0, 4, 4), x[1],
                                                  joint.block(4, 4, 4, 4), joint.block(0, 4, 4, 4));
    const FusedEstimate g = fuse_with_cross_covariance(x, joint);
    EXPECT_TRUE(b.P.isApprox(g.P, 1e-8)) << trial;
    EXPECT_TRUE(b.x.isApprox(g.x, 1e-8)) << trial;
  }
}

TEST(JointFusion, BlockDiagonalJointIsNaiveForThreeTracks) {
  std::mt19937_64 rng(7);
  const MatrixXd P[] = {random_spd(2, rng), random_spd(2, rng), random_spd(2, rng)};
  const VectorXd x[] = {VectorXd::Random(2), VectorXd::Random(2), VectorXd::Random(2)};
  MatrixXd joint = MatrixXd::Zero(6, 6);
  for (int i = 0; i < 3; ++i) joint.block(2 * i, 2 * i, 2, 2) = P[i];
  const FusedEstimate g = fuse_with_cross_covariance(x, joint);
  const FusedEstimate n = fuse_naive(x, P);
  EXPECT_TRUE(g.P.isApprox(n.P, 1e-10));
  EXPECT_TRUE(g.x.isApprox(n.x, 1e-10));
}

TEST(CovarianceIntersection, ScalarsPickTheBetterEstimate) {
  // 1-D: P(ω) = 1/(ω/4 + (1 − ω)/1) is smallest at ω = 0: the second estimate alone.
  const VectorXd x[] = {vec({0.0}), vec({5.0})};
  const MatrixXd P[] = {scalar(4.0), scalar(1.0)};
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant}) {
    const FusedEstimate f = fuse_covariance_intersection(x, P, {.criterion = c});
    EXPECT_NEAR(f.omega[0], 0.0, 1e-9);
    EXPECT_NEAR(f.P(0, 0), 1.0, 1e-9);
    EXPECT_NEAR(f.x[0], 5.0, 1e-8);
  }
}

TEST(CovarianceIntersection, SymmetricPairClosedForm) {
  // P1 = diag(1, 4), P2 = diag(4, 1): ω = 1/2 by symmetry, P = (½ diag(1, ¼) + ½ diag(¼, 1))⁻¹ = 1.6 I,
  // x = 1.6·½·(diag(1, ¼)·(0, 0) + diag(¼, 1)·(10, 10)) = (2, 8).
  const VectorXd x[] = {vec({0, 0}), vec({10, 10})};
  const MatrixXd P[] = {diag({1, 4}), diag({4, 1})};
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant}) {
    const FusedEstimate f = fuse_covariance_intersection(x, P, {.criterion = c});
    EXPECT_NEAR(f.omega[0], 0.5, 1e-7);
    EXPECT_TRUE(f.P.isApprox(diag({1.6, 1.6}), 1e-7));  // each element is linear in the ω error
    EXPECT_NEAR(f.x[0], 2.0, 1e-7);
    EXPECT_NEAR(f.x[1], 8.0, 1e-7);
  }
}

TEST(CovarianceIntersection, OmegaIsTheBruteForceGridOptimum) {
  std::mt19937_64 rng(11);
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant})
    for (int trial = 0; trial < 10; ++trial) {
      const MatrixXd P[] = {random_spd(4, rng), random_spd(4, rng)};
      const VectorXd x[] = {VectorXd::Random(4), VectorXd::Random(4)};
      double best = std::numeric_limits<double>::infinity(), best_w = -1;
      for (int g = 0; g <= 20000; ++g) {
        const double w = g / 20000.0, omega[] = {w, 1 - w};
        const double j = ci_criterion_value(P, omega, c);
        if (j < best) best = j, best_w = w;
      }
      const FusedEstimate f = fuse_covariance_intersection(x, P, {.criterion = c});
      const double value = c == CiCriterion::kTrace ? f.P.trace() : f.P.determinant();
      EXPECT_LE(value, best * (1 + 1e-9)) << trial;
      EXPECT_NEAR(f.omega[0], best_w, 2e-4) << trial;
      EXPECT_NEAR(f.omega[0] + f.omega[1], 1.0, 1e-12);
    }
}

TEST(CovarianceIntersection, ThreeTracksReachTheSimplexGridOptimum) {
  std::mt19937_64 rng(13);
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant})
    for (int trial = 0; trial < 4; ++trial) {
      const MatrixXd P[] = {random_spd(2, rng), random_spd(2, rng), random_spd(2, rng)};
      const VectorXd x[] = {VectorXd::Random(2), VectorXd::Random(2), VectorXd::Random(2)};
      double best = std::numeric_limits<double>::infinity();
      const int G = 400;
      for (int a = 0; a <= G; ++a)
        for (int b = 0; a + b <= G; ++b) {
          const double omega[] = {double(a) / G, double(b) / G, double(G - a - b) / G};
          best = std::min(best, ci_criterion_value(P, omega, c));
        }
      const FusedEstimate f = fuse_covariance_intersection(x, P, {.criterion = c});
      const double value = ci_criterion_value(P, f.omega, c);
      EXPECT_LE(value, best * (1 + 1e-9)) << trial;
      EXPECT_NEAR(f.omega[0] + f.omega[1] + f.omega[2], 1.0, 1e-12);
    }
}

TEST(CovarianceIntersection, IdenticalInputsGiveTheInputBack) {
  std::mt19937_64 rng(17);
  const MatrixXd P0 = random_spd(4, rng);
  const VectorXd x0 = VectorXd::Random(4);
  const VectorXd x[] = {x0, x0, x0};
  const MatrixXd P[] = {P0, P0, P0};
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant}) {
    const FusedEstimate f2 = fuse_covariance_intersection(std::span(x, 2), std::span(P, 2), {.criterion = c});
    const FusedEstimate f3 = fuse_covariance_intersection(x, P, {.criterion = c});
    EXPECT_TRUE(f2.P.isApprox(P0, 1e-10));
    EXPECT_TRUE(f2.x.isApprox(x0, 1e-10));
    EXPECT_TRUE(f3.P.isApprox(P0, 1e-10));
    EXPECT_TRUE(f3.x.isApprox(x0, 1e-10));
  }
}

// CI is consistent whatever the correlation: P_CI ≥ the actual covariance K Σ Kᵀ of its estimate
// x = Σ K_i x_i (K_i = ω_i P_CI P_i⁻¹), which is ≥ the Bar-Shalom–Campo P (the BLUE with the true Σ).
TEST(CovarianceIntersection, ConsistentAndNeverBelowBarShalomCampo) {
  std::mt19937_64 rng(19);
  for (CiCriterion c : {CiCriterion::kTrace, CiCriterion::kDeterminant})
    for (int trial = 0; trial < 30; ++trial) {
      const MatrixXd joint = random_spd(8, rng);
      const MatrixXd P[] = {joint.block(0, 0, 4, 4), joint.block(4, 4, 4, 4)};
      const VectorXd x[] = {VectorXd::Random(4), VectorXd::Random(4)};
      const FusedEstimate ci = fuse_covariance_intersection(x, P, {.criterion = c});
      const FusedEstimate bsc = fuse_bar_shalom_campo(x[0], P[0], x[1], P[1], joint.block(0, 4, 4, 4));
      MatrixXd K(4, 8);
      K.leftCols(4) = ci.omega[0] * ci.P * P[0].inverse();
      K.rightCols(4) = ci.omega[1] * ci.P * P[1].inverse();
      const MatrixXd actual = K * joint * K.transpose();
      const double min_eig = Eigen::SelfAdjointEigenSolver<MatrixXd>(ci.P - actual).eigenvalues().minCoeff();
      EXPECT_GE(min_eig, -1e-9 * ci.P.norm()) << trial;
      EXPECT_GE(ci.P.trace(), bsc.P.trace() - 1e-9) << trial;
      EXPECT_GE(actual.trace(), bsc.P.trace() - 1e-9) << trial;
    }
}

TEST(TrackFusion, BadInputsAreInputErrors) {
  const VectorXd x[] = {vec({0, 0}), vec({1, 1})};
  const MatrixXd bad[] = {diag({1, -1}), diag({1, 1})};
  EXPECT_THROW(fuse_naive(x, bad), InputError);
  EXPECT_THROW(fuse_covariance_intersection(x, bad, {}), InputError);
  const MatrixXd good[] = {diag({1, 1}), diag({1, 1})};
  // |P12| too large: P1 + P2 − 2 P12 = 0 is not positive definite.
  EXPECT_THROW(fuse_bar_shalom_campo(x[0], good[0], x[1], good[1], diag({1, 1})), InputError);
  const VectorXd mixed[] = {vec({0, 0}), vec({1})};
  EXPECT_THROW(fuse_naive(mixed, good), InputError);
  EXPECT_THROW(fuse_covariance_intersection(x, good, {.tolerance = 0.0}), InputError);
}

}  // namespace
}  // namespace trackassoc
