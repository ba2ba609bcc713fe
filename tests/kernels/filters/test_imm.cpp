// IMM bank (seed 002 §2): reduction to a single model when Π = I, Bayes' rule for the model
// probabilities, mixing of models of different state dimension checked against a hand-written
// Eigen implementation, thread-count determinism, option validation.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <cmath>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/imm.hpp"

namespace trackassoc {
namespace {

ImmOptions cv_ca(std::vector<double> pi, std::vector<double> mu0) {
  ImmOptions o;
  ImmModelSpec cv, ca;
  cv.kind = ImmModelKind::kConstantVelocity;
  cv.process_noise = 1.0;
  ca.kind = ImmModelKind::kConstantAcceleration;
  ca.process_noise = 5.0;
  o.models = {cv, ca};
  o.transition = std::move(pi);
  o.initial_probabilities = std::move(mu0);
  return o;
}

struct Scan {
  std::vector<double> z0, z1, r0, r1, r2;
  std::vector<uint8_t> det;
  PositionScan view() const {
    PositionScan s;
    s.z[0] = z0, s.z[1] = z1, s.R[0] = r0, s.R[1] = r1, s.R[2] = r2;
    s.detected = det;
    return s;
  }
};

Scan random_scan(CounterRng& rng, std::size_t n, double t) {
  Scan s;
  for (std::size_t i = 0; i < n; ++i) {
    // A target accelerating at 3 m/s² in x.
    s.z0.push_back(100.0 * t + 1.5 * t * t + rng.normal(0, 20));
    s.z1.push_back(-50.0 * t + rng.normal(0, 20));
    s.r0.push_back(400.0), s.r1.push_back(0.0), s.r2.push_back(400.0);
    s.det.push_back(rng.uniform() < 0.9);
  }
  return s;
}

void initialise_all(ImmBank& imm, std::vector<KinematicBank*> singles) {
  Eigen::Vector2d z1(0, 0), z2(100, -50);
  const Eigen::Matrix2d R = 400.0 * Eigen::Matrix2d::Identity();
  for (std::size_t i = 0; i < imm.size(); ++i) {
    imm.initialise(i, z1, R, z2, R, 1.0, 100.0);
    for (auto* b : singles) two_point_initialise(*b, i, z1, R, z2, R, 1.0, 100.0);
  }
}

TEST(Imm, IdentityTransitionWithCertainStartIsExactlyTheSingleModel) {
  const std::size_t N = 13;
  ImmBank imm(2, N, cv_ca({1, 0, 0, 1}, {1, 0}));
  KinematicBank cv(2, 2, N);
  initialise_all(imm, {&cv});
  KalmanOptions ko;
  ko.process_noise = 1.0;
  CounterRng rng(1);
  for (int k = 2; k < 12; ++k) {
    const Scan s = random_scan(rng, N, k);
    imm_bank_step(imm, 1.0, s.view());
    kalman_bank_step(cv, 1.0, s.view(), ko);
  }
  for (std::size_t i = 0; i < N; ++i) {
    EXPECT_EQ(imm.probability(i, 0), 1.0);
    EXPECT_EQ(imm.probability(i, 1), 0.0);
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(imm.combined().state(i, c), cv.state(i, c), 1e-12 * (1 + std::fabs(cv.state(i, c))));
    }
    for (int r = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c) {
        EXPECT_NEAR(imm.combined().cov(i, r, c), cv.cov(i, r, c),
                    1e-12 * std::sqrt(cv.cov(i, r, r) * cv.cov(i, c, c)));
      }
  }
}

// Π = I: no interaction, so each model is its own filter and μ_j(k) ∝ μ_j(k−1)·Λ_j(k).
TEST(Imm, IdentityTransitionFollowsBayesRule) {
  const std::size_t N = 11;
  ImmBank imm(2, N, cv_ca({1, 0, 0, 1}, {0.5, 0.5}));
  KinematicBank cv(2, 2, N), ca(2, 3, N);
  initialise_all(imm, {&cv, &ca});
  KalmanOptions kcv, kca;
  kcv.process_noise = 1.0;
  kca.model = KalmanModel::kConstantAcceleration;
  kca.process_noise = 5.0;
  std::vector<double> mu_cv(N, 0.5), ll_cv(N), ll_ca(N);
  CounterRng rng(2);
  for (int k = 2; k < 15; ++k) {
    const Scan s = random_scan(rng, N, k);
    imm_bank_step(imm, 1.0, s.view());
    kalman_bank_step(cv, 1.0, s.view(), kcv, {{}, ll_cv});
    kalman_bank_step(ca, 1.0, s.view(), kca, {{}, ll_ca});
    for (std::size_t i = 0; i < N; ++i) {
      const double a = mu_cv[i] * std::exp(ll_cv[i]), b = (1 - mu_cv[i]) * std::exp(ll_ca[i]);
      mu_cv[i] = a / (a + b);
    }
  }
  for (std::size_t i = 0; i < N; ++i) {
    EXPECT_NEAR(imm.probability(i, 0), mu_cv[i], 1e-10);
    EXPECT_NEAR(imm.probability(i, 0) + imm.probability(i, 1), 1.0, 1e-15);
    // Combined = Σ μ_j x_j, CV extended by CA's acceleration (so the acceleration is CA's).
    const double m = imm.probability(i, 0);
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(imm.combined().state(i, c), m * cv.state(i, c) + (1 - m) * ca.state(i, c),
                  1e-9 * (1 + std::fabs(ca.state(i, c))));
    }
    EXPECT_NEAR(imm.combined().state(i, 4), ca.state(i, 4), 1e-9 * (1 + std::fabs(ca.state(i, 4))));
  }
  // The accelerating target makes the CA model the more probable one.
  double mean_ca = 0;
  for (std::size_t i = 0; i < N; ++i) mean_ca += imm.probability(i, 1) / N;
  EXPECT_GT(mean_ca, 0.5);
}

// One mixing step with no prediction and no detection (dt = 0, all missed): the models must hold
// exactly the mixed initial conditions of Eq. 7, computed here by hand with Eigen, including the
// extension of the 4-D CV state by the CA model's own acceleration block.
TEST(Imm, MixingOfUnequalDimensionsMatchesHandComputation) {
  ImmBank imm(2, 1, cv_ca({0.9, 0.1, 0.2, 0.8}, {0.3, 0.7}));
  CounterRng rng(3);
  Eigen::VectorXd x1(4), x2(6);
  for (int c = 0; c < 4; ++c) x1[c] = rng.normal(0, 10);
  for (int c = 0; c < 6; ++c) x2[c] = rng.normal(0, 10);
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(4, 4), B = Eigen::MatrixXd::Random(6, 6);
  const Eigen::MatrixXd P1 = A * A.transpose() + Eigen::MatrixXd::Identity(4, 4);
  const Eigen::MatrixXd P2 = B * B.transpose() + Eigen::MatrixXd::Identity(6, 6);
  imm.model(0).filter().set(0, x1, P1);
  imm.model(1).filter().set(0, x2, P2);
  Scan s;
  s.z0 = s.z1 = s.r1 = {0.0};
  s.r0 = s.r2 = {1.0};
  s.det = {0};
  imm_bank_step(imm, 0.0, s.view());
  const double mu[2] = {0.3, 0.7}, pi[2][2] = {{0.9, 0.1}, {0.2, 0.8}};
  const double c1 = pi[0][0] * mu[0] + pi[1][0] * mu[1], c2 = pi[0][1] * mu[0] + pi[1][1] * mu[1];
  // Into CV (4-D): CA truncated.
  const double w11 = pi[0][0] * mu[0] / c1, w21 = pi[1][0] * mu[1] / c1;
  const Eigen::VectorXd m1 = w11 * x1 + w21 * x2.head(4);
  const Eigen::MatrixXd M1 =
      w11 * (P1 + (x1 - m1) * (x1 - m1).transpose()) +
      w21 * (P2.topLeftCorner(4, 4) + (x2.head(4) - m1) * (x2.head(4) - m1).transpose());
  // Into CA (6-D): CV extended by CA's own acceleration and its covariance block.
  Eigen::VectorXd x1e(6);
  x1e << x1, x2.tail(2);
  Eigen::MatrixXd P1e = Eigen::MatrixXd::Zero(6, 6);
  P1e.topLeftCorner(4, 4) = P1;
  P1e.bottomRightCorner(2, 2) = P2.bottomRightCorner(2, 2);
  const double w12 = pi[0][1] * mu[0] / c2, w22 = pi[1][1] * mu[1] / c2;
  const Eigen::VectorXd m2 = w12 * x1e + w22 * x2;
  const Eigen::MatrixXd M2 =
      w12 * (P1e + (x1e - m2) * (x1e - m2).transpose()) + w22 * (P2 + (x2 - m2) * (x2 - m2).transpose());
  EXPECT_LT((imm.model(0).filter().state_vector(0) - m1).norm(), 1e-12 * m1.norm());
  EXPECT_LT((imm.model(0).filter().covariance(0) - M1).norm(), 1e-12 * M1.norm());
  EXPECT_LT((imm.model(1).filter().state_vector(0) - m2).norm(), 1e-12 * m2.norm());
  EXPECT_LT((imm.model(1).filter().covariance(0) - M2).norm(), 1e-12 * M2.norm());
  // No detection: μ becomes the predicted c̄.
  EXPECT_NEAR(imm.probability(0, 0), c1, 1e-15);
  EXPECT_NEAR(imm.probability(0, 1), c2, 1e-15);
}

TEST(Imm, Seed002BankIsDeterministicAcrossThreads) {
  auto run = [](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    const std::size_t N = 3000;
    ImmOptions o = ImmOptions::seed002();
    o.grain_blocks = 8;
    ImmBank imm(2, N, o, trained_cs_network());
    initialise_all(imm, {});
    CounterRng rng(4);
    for (int k = 2; k < 8; ++k) imm_bank_step(imm, 1.0, random_scan(rng, N, k).view());
    std::vector<double> out;
    for (std::size_t i = 0; i < N; ++i) {
      for (int c = 0; c < 6; ++c) out.push_back(imm.combined().state(i, c));
      out.push_back(imm.probability(i, 0));
    }
    return out;
  };
  const auto a = run(1);
  EXPECT_EQ(a, run(2));
  for (double v : a) ASSERT_TRUE(std::isfinite(v));
}

TEST(Imm, RejectsBadOptions) {
  EXPECT_THROW(ImmBank(2, 1, cv_ca({0.9, 0.2, 0.1, 0.9}, {0.5, 0.5})), InputError);  // row 0 sums to 1.1
  EXPECT_THROW(ImmBank(2, 1, cv_ca({1, 0, 0, 1}, {0.5, 0.6})), InputError);
  EXPECT_THROW(ImmBank(2, 1, cv_ca({1, 0, 0}, {0.5, 0.5})), InputError);
  ImmOptions o = ImmOptions::seed002();
  o.models[0].cs_parallel.f2.a_max = -1;
  try {
    ImmBank bank(2, 1, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("models[0]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a_max"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trackassoc
