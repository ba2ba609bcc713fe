// Batched Kalman bank: hand-computed example, equality with the per-track Eigen reference, NEES
// consistency on a linear-Gaussian CV scenario, thread-count determinism, option validation.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/kalman_bank.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "tests/support/kalman_reference.hpp"

namespace trackassoc {
namespace {

// Holds the SoA measurement columns behind a PositionScan.
struct ScanData {
  std::vector<double> z[3], R[6];
  std::vector<uint8_t> detected;
  ScanData(std::size_t n) {
    for (auto& c : z) c.assign(n, 0.0);
    for (auto& c : R) c.assign(n, 0.0);
    detected.assign(n, 1);
  }
  PositionScan view(int d) const {
    PositionScan s;
    for (int a = 0; a < d; ++a) s.z[a] = z[a];
    for (int k = 0; k < d * (d + 1) / 2; ++k) s.R[k] = R[k];
    s.detected = detected;
    return s;
  }
};

// Per axis: x0 = [0, 10], P0 = diag(4, 4), T = 1, σ = 2 (Q1 = [[1, 2], [2, 4]]), R = 3,
// z1 = 13, z2 = 25. By hand:
//   predict 1: x = [10, 10], P = [[9, 6], [6, 8]];  S = 12, K = [3/4, 1/2], ν = 3
//   update 1:  x = [12.25, 11.5], P = [[2.25, 1.5], [1.5, 5]], NIS = 9/12 per axis
//   predict 2: x = [23.75, 11.5], P = [[11.25, 8.5], [8.5, 9]];  S = 57/4, ν = 1.25
//   update 2:  x = [1410/57, 698/57], P = [[135/57, 102/57], [102/57, 224/57]]
TEST(KalmanBank, HandComputedTwoSteps) {
  KinematicBank bank(2, 2, 1);
  Eigen::VectorXd x0(4);
  x0 << 0, 0, 10, 10;
  bank.set(0, x0, 4.0 * Eigen::MatrixXd::Identity(4, 4));
  KalmanOptions o;
  o.process_noise = 2.0;
  ScanData s(1);
  s.R[0][0] = 3.0, s.R[1][0] = 0.0, s.R[2][0] = 3.0;
  s.z[0][0] = 13.0, s.z[1][0] = 13.0;
  std::vector<double> nis(1);
  kalman_bank_step(bank, 1.0, s.view(2), o, {nis, {}});
  EXPECT_NEAR(nis[0], 1.5, 1e-12);
  EXPECT_NEAR(bank.state(0, 0), 12.25, 1e-12);
  EXPECT_NEAR(bank.state(0, 2), 11.5, 1e-12);
  EXPECT_NEAR(bank.cov(0, 0, 0), 2.25, 1e-12);
  EXPECT_NEAR(bank.cov(0, 0, 2), 1.5, 1e-12);
  EXPECT_NEAR(bank.cov(0, 2, 2), 5.0, 1e-12);
  s.z[0][0] = 25.0, s.z[1][0] = 25.0;
  kalman_bank_step(bank, 1.0, s.view(2), o);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(bank.state(0, a), 1410.0 / 57.0, 1e-12);
    EXPECT_NEAR(bank.state(0, 2 + a), 698.0 / 57.0, 1e-12);
    EXPECT_NEAR(bank.cov(0, a, a), 135.0 / 57.0, 1e-12);
    EXPECT_NEAR(bank.cov(0, a, 2 + a), 102.0 / 57.0, 1e-12);
    EXPECT_NEAR(bank.cov(0, 2 + a, 2 + a), 224.0 / 57.0, 1e-12);
  }
  // The axes never couple here.
  EXPECT_EQ(bank.cov(0, 0, 1), 0.0);
  EXPECT_EQ(bank.cov(0, 0, 3), 0.0);
  // A missed detection only predicts: P11 grows by P11 + 2 P12 + P22 + Q11.
  s.detected[0] = 0;
  kalman_bank_step(bank, 1.0, s.view(2), o);
  EXPECT_NEAR(bank.cov(0, 0, 0), (135.0 + 2 * 102.0 + 224.0) / 57.0 + 1.0, 1e-12);
  EXPECT_NEAR(bank.state(0, 0), 1410.0 / 57.0 + 698.0 / 57.0, 1e-12);
}

Eigen::MatrixXd random_spd(CounterRng& rng, int n, double scale) {
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = rng.normal();
  return scale * (A * A.transpose() + n * Eigen::MatrixXd::Identity(n, n));
}

double rel_err(double a, double b) { return std::fabs(a - b) / std::max(1.0, std::fabs(b)); }

class BankVsReference : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(BankVsReference, EqualsPerTrackEigenTo1e12) {
  const auto [d, n] = GetParam();
  const int D = d * n;
  const std::size_t N = 203;  // not a multiple of the 8 lanes: exercises the padded block
  CounterRng rng(7, d, n);
  KinematicBank bank(d, n, N);
  std::vector<ReferenceKalmanFilter> ref(N, ReferenceKalmanFilter(d, n, 1.5));
  for (std::size_t i = 0; i < N; ++i) {
    Eigen::VectorXd x(D);
    for (int c = 0; c < D; ++c) x[c] = rng.normal(0.0, 100.0);
    ref[i].x = x;
    ref[i].P = random_spd(rng, D, 10.0);
    bank.set(i, ref[i].x, ref[i].P);
  }
  KalmanOptions o;
  o.model = static_cast<KalmanModel>(n);
  o.process_noise = 1.5;
  o.grain_blocks = 3;
  ScanData s(N);
  std::vector<double> nis(N);
  for (int step = 0; step < 6; ++step) {
    const double dt = 0.5 + 0.25 * (step % 3);
    std::vector<Eigen::VectorXd> zs(N);
    std::vector<Eigen::MatrixXd> Rs(N);
    for (std::size_t i = 0; i < N; ++i) {
      zs[i] = ref[i].x.head(d) + Eigen::VectorXd::Constant(d, rng.normal(0.0, 30.0));
      Rs[i] = random_spd(rng, d, 50.0);
      for (int a = 0; a < d; ++a) s.z[a][i] = zs[i][a];
      for (int a = 0, k = 0; a < d; ++a)
        for (int b = a; b < d; ++b, ++k) s.R[k][i] = Rs[i](a, b);
      s.detected[i] = rng.uniform() < 0.8;
    }
    kalman_bank_step(bank, dt, s.view(d), o, {nis, {}});
    for (std::size_t i = 0; i < N; ++i) {
      ref[i].predict(dt);
      const double ref_nis = s.detected[i] ? ref[i].update(zs[i], Rs[i]) : 0.0;
      EXPECT_LE(rel_err(nis[i], ref_nis), 1e-12);
      for (int r = 0; r < D; ++r) {
        // Relative to the element's natural scale: |x_r| (or its σ) and √(P_rr·P_cc), since
        // off-diagonal covariances come out of cancellations.
        const double sx = std::max({1.0, std::fabs(ref[i].x[r]), std::sqrt(ref[i].P(r, r))});
        ASSERT_LE(std::fabs(bank.state(i, r) - ref[i].x[r]) / sx, 1e-12) << "track " << i << " step " << step;
        for (int c = r; c < D; ++c) {
          const double sp = std::max(1.0, std::sqrt(ref[i].P(r, r) * ref[i].P(c, c)));
          ASSERT_LE(std::fabs(bank.cov(i, r, c) - ref[i].P(r, c)) / sp, 1e-12)
              << "track " << i << " P(" << r << "," << c << ")";
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(CvCa2d3d, BankVsReference,
                         ::testing::Values(std::pair{2, 2}, std::pair{3, 2}, std::pair{2, 3},
                                           std::pair{3, 3}));

// Linear-Gaussian CV scenario: truth follows exactly the filter's model (discrete white-noise
// acceleration, σ = 1 m/s², T = 1 s), Cartesian measurements with R = diag(50², 80²), and the
// initial estimate drawn from N(truth, P0). Then NEES = x̃ᵀP⁻¹x̃ averaged over N tracks is
// χ²(N·D)/N: it must lie in its two-sided 95 % interval (Bar-Shalom et al. 2001, §5.4.2).
TEST(KalmanBank, NeesConsistentOnLinearGaussianCv) {
  const int d = 2, D = 4;
  const std::size_t N = 500;
  const double sigma = 1.0, T = 1.0;
  KinematicBank bank(d, 2, N);
  KalmanOptions o;
  o.process_noise = sigma;
  CounterRng rng(2024);
  Eigen::MatrixXd P0 = Eigen::MatrixXd::Identity(D, D);
  P0.diagonal() << 2500, 6400, 100, 100;
  std::vector<Eigen::VectorXd> truth(N);
  for (std::size_t i = 0; i < N; ++i) {
    truth[i] = Eigen::VectorXd(D);
    truth[i] << rng.uniform(-1e4, 1e4), rng.uniform(-1e4, 1e4), rng.normal(0, 100), rng.normal(0, 100);
    Eigen::VectorXd x0 = truth[i];
    for (int c = 0; c < D; ++c) x0[c] += std::sqrt(P0(c, c)) * rng.normal();
    bank.set(i, x0, P0);
  }
  ScanData s(N);
  const double lo = chi_square_quantile(0.025, static_cast<int>(N) * D) / N;
  const double hi = chi_square_quantile(0.975, static_cast<int>(N) * D) / N;
  for (int step = 1; step <= 30; ++step) {
    for (std::size_t i = 0; i < N; ++i) {
      const double ax = sigma * rng.normal(), ay = sigma * rng.normal();
      truth[i][0] += truth[i][2] * T + 0.5 * T * T * ax;
      truth[i][1] += truth[i][3] * T + 0.5 * T * T * ay;
      truth[i][2] += T * ax;
      truth[i][3] += T * ay;
      s.z[0][i] = truth[i][0] + 50.0 * rng.normal();
      s.z[1][i] = truth[i][1] + 80.0 * rng.normal();
      s.R[0][i] = 2500.0, s.R[1][i] = 0.0, s.R[2][i] = 6400.0;
    }
    kalman_bank_step(bank, T, s.view(d), o);
    if (step % 10 != 0) continue;
    double nees = 0.0;
    for (std::size_t i = 0; i < N; ++i) {
      const Eigen::VectorXd e = bank.state_vector(i) - truth[i];
      nees += e.dot(bank.covariance(i).ldlt().solve(e));
    }
    nees /= N;
    EXPECT_GT(nees, lo) << "step " << step;
    EXPECT_LT(nees, hi) << "step " << step;
  }
}

TEST(KalmanBank, BitIdenticalForOneAndTwoThreads) {
  auto run = [](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    const std::size_t N = 5000;
    KinematicBank bank(3, 2, N);
    CounterRng rng(3);
    ScanData s(N);
    KalmanOptions o;
    o.grain_blocks = 4;
    for (int step = 0; step < 3; ++step) {
      for (std::size_t i = 0; i < N; ++i) {
        for (int a = 0; a < 3; ++a) s.z[a][i] = rng.normal(0, 100);
        s.R[0][i] = s.R[3][i] = s.R[5][i] = 100.0;
        s.detected[i] = rng.uniform() < 0.5;
      }
      kalman_bank_step(bank, 1.0, s.view(3), o);
    }
    std::vector<double> all;
    for (std::size_t i = 0; i < N; ++i)
      for (int c = 0; c < 6; ++c) all.push_back(bank.state(i, c));
    return all;
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(KalmanBank, RejectsBadOptionsAndScans) {
  KinematicBank bank(2, 2, 10);
  ScanData s(10);
  KalmanOptions o;
  o.process_noise = -1.0;
  EXPECT_THROW(kalman_bank_step(bank, 1.0, s.view(2), o), InputError);
  o.process_noise = 1.0;
  EXPECT_THROW(kalman_bank_step(bank, -1.0, s.view(2), o), InputError);
  o.model = KalmanModel::kConstantAcceleration;
  EXPECT_THROW(kalman_bank_step(bank, 1.0, s.view(2), o), InputError);
  o.model = KalmanModel::kConstantVelocity;
  ScanData short_scan(9);
  EXPECT_THROW(kalman_bank_step(bank, 1.0, short_scan.view(2), o), InputError);
  try {
    o.process_noise = std::nan("");
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("process_noise"), std::string::npos);
  }
  EXPECT_THROW(KinematicBank(4, 2, 1), InputError);
}

}  // namespace
}  // namespace trackassoc
