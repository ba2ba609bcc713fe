// Alignment at common times, the sequential statistic (seed 000 Eq. 1–2), its correlated form and
// the chi-square gate, against numbers worked out by hand.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {
namespace {

// Builds AlignedTracks with dim d and K times from explicit states and full covariances.
struct AlignedBuilder {
  AlignedTracks x;
  AlignedBuilder(int32_t sensor, int d, int K, int n) {
    x.sensor = sensor;
    x.dim = d;
    x.n_times = K;
    for (int i = 0; i < n; ++i) {
      x.track.push_back(i);
      x.truth.push_back(-1);
    }
    x.allocate_full();
  }
  void set(int i, int k, std::vector<double> state, std::vector<std::vector<double>> P) {
    const int d = x.dim;
    const int64_t cell = x.cell(i, k);
    x.valid[cell] = 1;
    for (int c = 0; c < d; ++c) x.state_at(cell)[c] = state[c];
    for (int r = 0, p = 0; r < d; ++r)
      for (int c = r; c < d; ++c, ++p) x.cov_at(cell)[p] = P[r][c];
  }
};

TEST(ChiSquareQuantile, MatchesTableValues) {
  // Abramowitz & Stegun Table 26.8 / any chi-square table.
  EXPECT_NEAR(chi_square_quantile(0.99, 4), 13.2767, 1e-4);
  EXPECT_NEAR(chi_square_quantile(0.95, 10), 18.3070, 1e-4);
  EXPECT_NEAR(chi_square_quantile(0.999, 100), 149.449, 1e-3);
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.84146, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.5, 2), 2.0 * std::log(2.0), 1e-10);  // exponential: −2 ln(1−p)
  EXPECT_NEAR(chi_square_quantile(0.01, 6), 0.872090, 1e-5);
  EXPECT_THROW(chi_square_quantile(1.0, 4), InputError);
  EXPECT_THROW(chi_square_quantile(0.5, 0), InputError);
}

// Two 2-D states (D = 2), two common times.
//  k=0: d = (1,2) − (0,0) = (1,2); C = [[2,1],[1,2]] + I = [[3,1],[1,3]], det 8,
//       C⁻¹ = [[3,−1],[−1,3]]/8, dᵀC⁻¹d = (3·1 − 2·1·2 + 3·4)/8 = 11/8.
//  k=1: d = (3,−1) − (1,1) = (2,−2); C = I + [[1,.5],[.5,1]] = [[2,.5],[.5,2]], det 3.75,
//       dᵀC⁻¹d = (2·4 + 2·.5·4 + 2·4)/3.75 = 20/3.75 = 16/3.
//  λ = 11/8 + 16/3 = 161/24 ≈ 6.7083, dof = 4.
TEST(SequentialStatistic, HandCalculationTwoTimes) {
  AlignedBuilder a(1, 2, 2, 1), b(2, 2, 2, 1);
  a.set(0, 0, {1, 2}, {{2, 1}, {1, 2}});
  b.set(0, 0, {0, 0}, {{1, 0}, {0, 1}});
  a.set(0, 1, {3, -1}, {{1, 0}, {0, 1}});
  b.set(0, 1, {1, 1}, {{1, 0.5}, {0.5, 1}});
  StatisticOptions opt;
  opt.gate_probability = 0.99;  // χ²_0.99(4) = 13.28 > 6.71: in the gate
  PairStatistic s = independent_sequential_statistic(a.x, b.x, opt);
  ASSERT_EQ(s.lambda.size(), 1u);
  EXPECT_NEAR(s.lambda[0], 161.0 / 24.0, 1e-12);
  EXPECT_EQ(s.dof[0], 4);
  EXPECT_EQ(s.in_gate[0], 1);
  opt.gate_probability = 0.5;  // χ²_0.5(4) = 3.357 < 6.71: gated out
  s = independent_sequential_statistic(a.x, b.x, opt);
  EXPECT_EQ(s.in_gate[0], 0);
  opt.gate_probability = 1.0;  // gating disabled
  s = independent_sequential_statistic(a.x, b.x, opt);
  EXPECT_EQ(s.in_gate[0], 1);
}

// 4-D states with diagonal covariances; track b1 misses time 1 and b2 never coexists with a0.
//  a0/b0: k=0 d=(3,4,0,0), C=diag(2,2,1,1)+diag(1,2,1,1)=diag(3,4,2,2): 9/3+16/4 = 7;
//         k=1 d=(0,0,2,2), C=diag(2,2,2,2): 2+2 = 4. λ = 11, dof 8.
//  a0/b1: k=0 d=(0,0,1,0), C=diag(2,2,1,1)+diag(1,1,1,1)=diag(3,3,2,2): 1/2. λ = 0.5, dof 4.
//  a0/b2: λ = 0, dof 0, out of the gate.
TEST(SequentialStatistic, FixedSizeFourStateAndMissingTimes) {
  AlignedBuilder a(0, 4, 2, 1), b(1, 4, 2, 3);
  auto diag = [](double p, double q, double r, double s) {
    return std::vector<std::vector<double>>{{p, 0, 0, 0}, {0, q, 0, 0}, {0, 0, r, 0}, {0, 0, 0, s}};
  };
  a.set(0, 0, {3, 4, 1, 1}, diag(2, 2, 1, 1));
  a.set(0, 1, {10, 10, 3, 3}, diag(1, 1, 1, 1));
  b.set(0, 0, {0, 0, 1, 1}, diag(1, 2, 1, 1));
  b.set(0, 1, {10, 10, 1, 1}, diag(1, 1, 1, 1));
  b.set(1, 0, {3, 4, 0, 1}, diag(1, 1, 1, 1));
  PairStatistic s = independent_sequential_statistic(a.x, b.x, StatisticOptions{});
  ASSERT_EQ(s.n_a, 1);
  ASSERT_EQ(s.n_b, 3);
  EXPECT_NEAR(s.lambda[0], 11.0, 1e-12);
  EXPECT_EQ(s.dof[0], 8);
  EXPECT_EQ(s.in_gate[0], 1);  // χ²_0.99(8) = 20.09
  EXPECT_NEAR(s.lambda[1], 0.5, 1e-12);
  EXPECT_EQ(s.dof[1], 4);
  EXPECT_EQ(s.lambda[2], 0.0);
  EXPECT_EQ(s.dof[2], 0);
  EXPECT_EQ(s.in_gate[2], 0);
}

// Correlated form, C = P_a + P_b − ρ(S_a S_b + S_b S_a) with S = P^{1/2}:
//  P_a = diag(4,1), P_b = diag(1,9): S_a = diag(2,1), S_b = diag(1,3), S_a S_b = diag(2,3);
//  ρ = 0.5: C = diag(5,10) − 0.5·diag(4,6) = diag(3,7); d = (3,7): 9/3 + 49/7 = 10.
//  Independent form: C = diag(5,10): 9/5 + 49/10 = 6.7.
TEST(SequentialStatistic, CorrelatedBarShalomCampoHand) {
  AlignedBuilder a(0, 2, 1, 1), b(1, 2, 1, 1);
  a.set(0, 0, {3, 7}, {{4, 0}, {0, 1}});
  b.set(0, 0, {0, 0}, {{1, 0}, {0, 9}});
  StatisticOptions opt;
  EXPECT_NEAR(independent_sequential_statistic(a.x, b.x, opt).lambda[0], 6.7, 1e-12);
  opt.correlated = true;
  opt.cross_correlation = 0.5;
  EXPECT_NEAR(independent_sequential_statistic(a.x, b.x, opt).lambda[0], 10.0, 1e-12);
}

// Non-commuting covariances: C must stay SPD for ρ → 1, and equal (1−ρ)(P_a+P_b) + ρ(S_a−S_b)².
// With S_a = [[2,1],[1,2]] (P_a = [[5,4],[4,5]]) and S_b = I (P_b = I), ρ = 0.9:
//  directly: P_a + P_b − ρ·2S_a = [[6,4],[4,6]] − 0.9·[[4,2],[2,4]] = [[2.4,2.2],[2.2,2.4]];
//  check: 0.1·[[6,4],[4,6]] + 0.9·(S_a − S_b)², (S_a − S_b)² = [[1,1],[1,1]]² = [[2,2],[2,2]], the same.
//  det = 5.76 − 4.84 = 0.92.
//  d = (1,0): dᵀC⁻¹d = 2.4/0.92.
TEST(SequentialStatistic, CorrelatedNonCommutingStaysPositiveDefinite) {
  AlignedBuilder a(0, 2, 1, 1), b(1, 2, 1, 1);
  a.set(0, 0, {1, 0}, {{5, 4}, {4, 5}});
  b.set(0, 0, {0, 0}, {{1, 0}, {0, 1}});
  StatisticOptions opt;
  opt.correlated = true;
  opt.cross_correlation = 0.9;
  EXPECT_NEAR(independent_sequential_statistic(a.x, b.x, opt).lambda[0], 2.4 / 0.92, 1e-10);
}

TEST(SequentialStatistic, BadInputRaisesInputError) {
  AlignedBuilder a(0, 2, 1, 1), b(1, 2, 1, 1);
  a.set(0, 0, {1, 0}, {{-1, 0}, {0, -1}});
  b.set(0, 0, {0, 0}, {{0.5, 0}, {0, 0.5}});
  EXPECT_THROW(independent_sequential_statistic(a.x, b.x, StatisticOptions{}), InputError);
  StatisticOptions bad;
  bad.cross_correlation = 1.0;
  EXPECT_THROW(bad.validate(), InputError);
  bad = {};
  bad.gate_probability = 0.0;
  EXPECT_THROW(bad.validate(), InputError);
  AlignedBuilder c(2, 4, 1, 1);
  EXPECT_THROW(independent_sequential_statistic(a.x, c.x, StatisticOptions{}), InputError);
}

// Under H0 (same target, independent errors) λ is χ²(D·K): the gate keeps about p of the true pairs.
TEST(SequentialStatistic, GateKeepsTheGateProbabilityOfTruePairs) {
  const int n = 400, K = 3, D = 4;
  AlignedBuilder a(0, D, K, n), b(1, D, K, n);
  CounterRng rng(7, 0, 1);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < K; ++k) {
      const double sa = 1.0 + i % 3, sb = 2.0;  // standard deviations per component
      std::vector<double> xa(D), xb(D);
      for (int c = 0; c < D; ++c) {
        const double truth = 100.0 * i + 10.0 * k + c;
        xa[c] = truth + sa * rng.normal();
        xb[c] = truth + sb * rng.normal();
      }
      std::vector<std::vector<double>> Pa(D, std::vector<double>(D, 0.0)), Pb = Pa;
      for (int c = 0; c < D; ++c) {
        Pa[c][c] = sa * sa;
        Pb[c][c] = sb * sb;
      }
      a.set(i, k, xa, Pa);
      b.set(i, k, xb, Pb);
    }
  StatisticOptions opt;
  opt.gate_probability = 0.95;
  // Independent scans: the χ²(n·D) gate of seed 000 holds exactly; the calibrated gate (built for
  // correlated scans, tests/kernels/statistics/test_gate_calibration.cpp) is conservative here, never below
  // nominal.
  StatisticOptions calibrated = opt;
  opt.gate = GateMethod::kChiSquareSum;
  const PairStatistic s = independent_sequential_statistic(a.x, b.x, opt);
  const PairStatistic sc = independent_sequential_statistic(a.x, b.x, calibrated);
  int kept_calibrated = 0;
  for (int i = 0; i < n; ++i) kept_calibrated += sc.in_gate[static_cast<std::size_t>(i) * n + i];
  EXPECT_GE(kept_calibrated / double(n), 0.95 - 0.03);
  EXPECT_EQ(sc.in_gate[1], 0);
  int kept = 0;
  double mean = 0.0;
  for (int i = 0; i < n; ++i) {
    kept += s.in_gate[static_cast<std::size_t>(i) * n + i];
    mean += s.lambda[static_cast<std::size_t>(i) * n + i] / n;
  }
  // Binomial(400, 0.95): σ ≈ 0.011; mean of χ²(12) is 12 with σ of the mean ≈ 0.25.
  EXPECT_NEAR(kept / double(n), 0.95, 0.045);
  EXPECT_NEAR(mean, 12.0, 1.2);
  // Tracks 100 m apart are never in the gate.
  EXPECT_EQ(s.in_gate[1], 0);
  EXPECT_EQ(s.in_gate[static_cast<std::size_t>(n)], 0);
}

TEST(SequentialStatistic, OneAndTwoThreadsBitIdentical) {
  const int na = 57, nb = 43, K = 6, D = 6;
  AlignedBuilder a(0, D, K, na), b(1, D, K, nb);
  CounterRng rng(11, 2, 3);
  for (auto* x : {&a, &b})
    for (int i = 0; i < x->x.n_tracks(); ++i)
      for (int k = 0; k < K; ++k) {
        if (rng.uniform() < 0.1) continue;  // some missing times
        std::vector<double> s(D);
        for (auto& v : s) v = rng.uniform(-5, 5);
        std::vector<std::vector<double>> P(D, std::vector<double>(D, 0.0));
        for (int r = 0; r < D; ++r) {
          P[r][r] = rng.uniform(1.0, 3.0);
          if (r + 1 < D) P[r][r + 1] = P[r + 1][r] = rng.uniform(-0.4, 0.4);
        }
        x->set(i, k, s, P);
      }
  for (bool correlated : {false, true}) {
    StatisticOptions opt;
    opt.correlated = correlated;
    opt.cross_correlation = correlated ? 0.3 : 0.0;
    PairStatistic s1, s2;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
      s1 = independent_sequential_statistic(a.x, b.x, opt);
    }
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
      s2 = independent_sequential_statistic(a.x, b.x, opt);
    }
    ASSERT_EQ(s1.lambda.size(), s2.lambda.size());
    EXPECT_EQ(0, std::memcmp(s1.lambda.data(), s2.lambda.data(), s1.lambda.size() * sizeof(double)));
    EXPECT_EQ(s1.dof, s2.dof);
    EXPECT_EQ(s1.in_gate, s2.in_gate);
  }
}

// A track reported at t=0 and t=2, predicted to t=1 with the CV model and continuous white-noise
// acceleration, σ = 2 m/s² (q = 4), Δ = 1, per axis:
//  position: 0 + 1·10 = 10 (x), 0 + 1·(−5) = −5 (y);
//  P = F P Fᵀ + Q with P = diag(pos 4, vel 1):  pos 4 + Δ²·1 + q/3 = 5 + 4/3 = 19/3,
//  pos-vel Δ·1 + q/2 = 1 + 2 = 3, vel 1 + q = 5; x and y do not mix.
// At t=3.5 from the t=2 report (P = diag(1, 1, 0.25, 0.25)), Δ = 1.5:
//  x = 20 + 15 = 35; pos var 1 + 2.25·0.25 + 4·3.375/3 = 1.5625 + 4.5 = 6.0625;
//  pos-vel 1.5·0.25 + 4·2.25/2 = 0.375 + 4.5 = 4.875; vel 0.25 + 4·1.5 = 6.25.
TEST(AlignTracks, CvPredictionHandExample) {
  TrackTable tt(StateLayout::kXY_VXVY);
  Eigen::MatrixXd P0 = Eigen::Vector4d(4, 4, 1, 1).asDiagonal();
  Eigen::MatrixXd P2 = Eigen::Vector4d(1, 1, 0.25, 0.25).asDiagonal();
  tt.push_back(3, 7, 2.0, Eigen::Vector4d(20, -10, 10, -5), P2, 42);  // out of time order on purpose
  tt.push_back(3, 7, 0.0, Eigen::Vector4d(0, 0, 10, -5), P0, 42);
  tt.push_back(9, 7, 1.0, Eigen::Vector4d(1e6, 0, 0, 0), P0, 1);  // another sensor: ignored
  tt.push_back(3, 2, 0.5, Eigen::Vector4d(1, 1, 1, 1), P0, 5);    // track 2 sorts first
  const std::vector<double> times{-1.0, 1.0, 2.0, 3.5, 20.0};
  AlignmentOptions opt;
  opt.method = AlignmentMethod::kForward;  // this example is the forward prediction of seed 000
  opt.process_noise = 2.0;
  opt.max_extrapolation = 10.0;
  const AlignedTracks al = align_tracks(tt, 3, times, opt);
  ASSERT_EQ(al.n_tracks(), 2);
  EXPECT_EQ(al.track[0], 2);
  EXPECT_EQ(al.track[1], 7);
  EXPECT_EQ(al.truth[1], 42);
  ASSERT_EQ(al.n_times, 5);
  const int D = 4;
  auto valid = [&](int a, int k) { return al.valid_at(a, k); };
  auto x = [&](int a, int k, int c) { return al.state_at(al.cell(a, k))[c]; };
  auto cov = [&](int a, int k, int r, int c) { return al.cov_at(al.cell(a, k))[packed_index(D, r, c)]; };
  EXPECT_FALSE(valid(1, 0));  // before the first report
  ASSERT_TRUE(valid(1, 1));
  EXPECT_NEAR(x(1, 1, 0), 10.0, 1e-12);
  EXPECT_NEAR(x(1, 1, 1), -5.0, 1e-12);
  EXPECT_NEAR(x(1, 1, 2), 10.0, 1e-12);
  EXPECT_NEAR(x(1, 1, 3), -5.0, 1e-12);
  for (int axis = 0; axis < 2; ++axis) {
    EXPECT_NEAR(cov(1, 1, axis, axis), 19.0 / 3.0, 1e-12);
    EXPECT_NEAR(cov(1, 1, axis, axis + 2), 3.0, 1e-12);
    EXPECT_NEAR(cov(1, 1, axis + 2, axis + 2), 5.0, 1e-12);
  }
  EXPECT_EQ(cov(1, 1, 0, 1), 0.0);
  EXPECT_EQ(cov(1, 1, 0, 3), 0.0);
  ASSERT_TRUE(valid(1, 2));  // exactly at a report: the report itself
  EXPECT_EQ(x(1, 2, 0), 20.0);
  EXPECT_EQ(cov(1, 2, 0, 0), 1.0);
  EXPECT_EQ(cov(1, 2, 2, 2), 0.25);
  ASSERT_TRUE(valid(1, 3));
  EXPECT_NEAR(x(1, 3, 0), 35.0, 1e-12);
  EXPECT_NEAR(x(1, 3, 1), -17.5, 1e-12);
  EXPECT_NEAR(cov(1, 3, 0, 0), 6.0625, 1e-12);
  EXPECT_NEAR(cov(1, 3, 0, 2), 4.875, 1e-12);
  EXPECT_NEAR(cov(1, 3, 2, 2), 6.25, 1e-12);
  EXPECT_FALSE(valid(1, 4));  // 18 s old > max_extrapolation
  EXPECT_FALSE(valid(0, 0));
  EXPECT_TRUE(valid(0, 1));
  EXPECT_NEAR(x(0, 1, 0), 1.5, 1e-12);

  const std::vector<double> unsorted{1.0, 0.5};
  EXPECT_THROW(align_tracks(tt, 3, unsorted, opt), InputError);
  AlignmentOptions bad;
  bad.process_noise = -1.0;
  EXPECT_THROW(align_tracks(tt, 3, times, bad), InputError);
  EXPECT_EQ(align_tracks(tt, 5, times, opt).n_tracks(), 0);  // a sensor without tracks
}

}  // namespace
}  // namespace trackassoc
