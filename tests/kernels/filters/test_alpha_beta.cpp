// Alpha-beta filter bank (kernels/filters/alpha_beta.hpp): a hand-computed example, Kalata gains against the
// steady-state Kalman filter (Riccati iteration), the steady covariance against Lyapunov iteration
// and the closed-form noise-reduction ratios, the detected mask, and 1 vs 2 threads.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/alpha_beta.hpp"

using namespace trackassoc;

namespace {
AlphaBetaOptions fixed(double a, double b) {
  AlphaBetaOptions o;
  o.gains = AlphaBetaGainMode::kFixed;
  o.alpha = a;
  o.beta = b;
  o.expanding_memory_start = false;
  return o;
}
}  // namespace

TEST(AlphaBeta, HandComputedTwoSteps) {
  // α = 0.5, β = 0.2. x: p=0, v=10. y: p=100, v=-5.
  AlphaBetaBank bank(2, 1, fixed(0.5, 0.2));
  const double p0[2] = {0.0, 100.0}, v0[2] = {10.0, -5.0};
  bank.initialise(0, p0, v0);
  bank.predict(1.0);  // x: p=10; y: p=95
  std::vector<double> zx{12.0}, zy{94.0};
  std::vector<std::span<const double>> z{zx, zy};
  std::vector<uint8_t> det{1};
  bank.update(z, det);
  // x: r=2 → p=11, v=10+0.2·2=10.4. y: r=-1 → p=94.5, v=-5-0.2=-5.2.
  EXPECT_DOUBLE_EQ(bank.position[0][0], 11.0);
  EXPECT_DOUBLE_EQ(bank.velocity[0][0], 10.4);
  EXPECT_DOUBLE_EQ(bank.position[1][0], 94.5);
  EXPECT_DOUBLE_EQ(bank.velocity[1][0], -5.2);
  bank.predict(2.0);  // x: p = 11 + 20.8 = 31.8
  zx[0] = 30.0;
  zy[0] = 84.0;  // y: p = 94.5 - 10.4 = 84.1, r = -0.1
  bank.update(z, det);
  // x: r = -1.8 → p = 30.9, v = 10.4 + (0.2/2)(-1.8) = 10.22.
  EXPECT_NEAR(bank.position[0][0], 30.9, 1e-12);
  EXPECT_NEAR(bank.velocity[0][0], 10.22, 1e-12);
  EXPECT_NEAR(bank.position[1][0], 84.05, 1e-12);
  EXPECT_NEAR(bank.velocity[1][0], -5.21, 1e-12);
}

TEST(AlphaBeta, ExpandingMemoryStartIsTheLeastSquaresLineFit) {
  // With tiny steady gains the filter stays in its expanding-memory start, whose estimate after
  // n measurements equals the least-squares straight line through them (Brookner §1.2.6).
  AlphaBetaOptions o = fixed(1e-4, 1e-6);
  o.expanding_memory_start = true;
  AlphaBetaBank bank(2, 1, o);
  const double zero[2] = {0.0, 0.0}, junk[2] = {123.0, -45.0};
  bank.initialise(0, zero, junk, /*measurements=*/0);
  CounterRng rng(3);
  const double T = 2.0;
  std::vector<double> ts, zs;
  for (int k = 0; k < 12; ++k) {
    const double t = k * T, zx = 5.0 + 3.0 * t + rng.normal(0, 4);
    if (k > 0)
      bank.predict(T);
    else
      bank.step[0] = T;  // the first measurement: no prediction, but a defined step
    const double z[2] = {zx, -zx};
    bank.update_track(0, z);
    ts.push_back(t);
    zs.push_back(zx);
    if (k < 1) continue;
    // Least squares z ≈ c0 + c1·t, evaluated at t.
    Eigen::MatrixXd A(ts.size(), 2);
    Eigen::VectorXd b(ts.size());
    for (std::size_t r = 0; r < ts.size(); ++r) {
      A(r, 0) = 1.0;
      A(r, 1) = ts[r];
      b(r) = zs[r];
    }
    const Eigen::Vector2d c = A.colPivHouseholderQr().solve(b);
    EXPECT_NEAR(bank.position[0][0], c(0) + c(1) * t, 1e-9) << "k=" << k;
    EXPECT_NEAR(bank.velocity[0][0], c(1), 1e-9) << "k=" << k;
    EXPECT_NEAR(bank.position[1][0], -(c(0) + c(1) * t), 1e-9) << "k=" << k;
  }
  EXPECT_EQ(bank.measurements[0], 12);
  // g_n, h_n by hand: n = 2 → 10/12, 1/2.
  EXPECT_NEAR(expanding_memory_gains(2).alpha, 10.0 / 12.0, 1e-15);
  EXPECT_NEAR(expanding_memory_gains(2).beta, 0.5, 1e-15);
}

TEST(AlphaBeta, KalataGainsAreTheSteadyStateKalmanGains) {
  for (double sw : {0.5, 2.0, 20.0}) {
    for (double T : {0.5, 1.0, 4.0}) {
      const double sv = 100.0;
      Eigen::Matrix2d F, Q, P = Eigen::Matrix2d::Identity() * 1e6;
      F << 1, T, 0, 1;
      Q << T * T * T * T / 4, T * T * T / 2, T * T * T / 2, T * T;
      Q *= sw * sw;
      Eigen::Vector2d K;
      for (int it = 0; it < 20000; ++it) {
        const Eigen::Matrix2d M = F * P * F.transpose() + Q;
        K = M.col(0) / (M(0, 0) + sv * sv);
        P = M - K * M.row(0);
      }
      const AlphaBetaGains g = kalata_gains(tracking_index(sw, sv, T));
      EXPECT_NEAR(g.alpha, K(0), 1e-9) << "sw=" << sw << " T=" << T;
      EXPECT_NEAR(g.beta, K(1) * T, 1e-9) << "sw=" << sw << " T=" << T;
      // Kalata's identity β = 2(2 − α) − 4√(1 − α).
      EXPECT_NEAR(g.beta, 2 * (2 - g.alpha) - 4 * std::sqrt(1 - g.alpha), 1e-9);
      // The steady covariance of the optimal loop is the Kalman one: P_pp = α σ_v², P_pv = β σ_v²/T.
      const auto c = alpha_beta_steady_covariance(g, T, sw, sv);
      EXPECT_NEAR(c[0], g.alpha * sv * sv, 1e-6 * sv * sv);
      EXPECT_NEAR(c[1], g.beta / T * sv * sv, 1e-6 * sv * sv);
      EXPECT_NEAR(c[2], P(1, 1), 1e-6 * P(1, 1));
    }
  }
}

TEST(AlphaBeta, SteadyCovarianceMatchesNoiseReductionRatios) {
  // No process noise: Benedict–Bordner / Kalata variance-reduction ratios of the α-β filter.
  const double a = 0.6, b = 0.3, T = 2.0, sv = 10.0;
  const double den = a * (4 - 2 * a - b);
  const auto c = alpha_beta_steady_covariance({a, b}, T, 0.0, sv);
  EXPECT_NEAR(c[0], sv * sv * (2 * a * a + 2 * b - 3 * a * b) / den, 1e-9);
  EXPECT_NEAR(c[2], sv * sv * 2 * b * b / (den * T * T), 1e-9);
  EXPECT_NEAR(c[1], sv * sv * b * (2 * a - b) / (den * T), 1e-9);
  EXPECT_THROW(alpha_beta_steady_covariance({0.5, 3.5}, T, 0.0, sv), InputError);
}

TEST(AlphaBeta, MaskBatchAndPerTrackAgree3D) {
  AlphaBetaOptions o;  // Kalata
  o.process_noise = 3.0;
  o.measurement_noise = 50.0;
  o.grain = 7;
  const std::size_t n = 101;
  AlphaBetaBank batch(3, n, o), single(3, n, o);
  CounterRng rng(5);
  for (std::size_t i = 0; i < n; ++i) {
    const double p[3] = {rng.normal(0, 1000), rng.normal(0, 1000), rng.normal(0, 1000)};
    const double v[3] = {rng.normal(0, 100), rng.normal(0, 100), rng.normal(0, 10)};
    batch.initialise(i, p, v);
    single.initialise(i, p, v);
  }
  std::array<std::vector<double>, 3> z;
  std::vector<uint8_t> det(n);
  for (int scan = 0; scan < 5; ++scan) {
    for (auto& c : z) {
      c.resize(n);
      for (auto& x : c) x = rng.normal(0, 1000);
    }
    for (auto& d : det) d = rng.uniform() < 0.7;
    const std::vector<double> before = batch.position[0];
    batch.predict(1.5);
    batch.update(std::vector<std::span<const double>>{z[0], z[1], z[2]}, det);
    for (std::size_t i = 0; i < n; ++i) {
      single.predict_track(i, 1.5);
      if (det[i]) single.update_track(i, std::array<double, 3>{z[0][i], z[1][i], z[2][i]});
      if (!det[i]) {
        EXPECT_DOUBLE_EQ(batch.position[0][i], before[i] + 1.5 * batch.velocity[0][i]);
      }
    }
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(batch.position[a], single.position[a]);
    EXPECT_EQ(batch.velocity[a], single.velocity[a]);
  }
}

TEST(AlphaBeta, OneAndTwoThreadsBitIdentical) {
  auto run = [](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    AlphaBetaOptions o;
    o.grain = 64;
    const std::size_t n = 5000;
    AlphaBetaBank bank(2, n, o);
    CounterRng rng(9);
    std::vector<double> zx(n), zy(n), steps(n);
    std::vector<uint8_t> det(n, 1);
    for (int scan = 0; scan < 4; ++scan) {
      for (std::size_t i = 0; i < n; ++i) {
        zx[i] = rng.normal(100.0 * scan, 50);
        zy[i] = rng.normal(0, 50);
        steps[i] = 0.5 + rng.uniform();
      }
      bank.predict(steps);
      bank.update(std::vector<std::span<const double>>{zx, zy}, det);
    }
    return bank.position[0];
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(AlphaBeta, ValidateNamesTheField) {
  AlphaBetaOptions o = fixed(2.5, 0.1);
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("alpha"), std::string::npos);
  }
  o = AlphaBetaOptions{};
  o.measurement_noise = 0;
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_THROW(AlphaBetaBank(4, 1, AlphaBetaOptions{}), InputError);
}
