// The whiteness test that decides whether a sensor's reports are a filter's output, so that the
// alignment's lag terms apply (kernels/statistics/report_whiteness.hpp): a hand-calculated ratio, a
// CV Kalman filter's output against reports with independent errors (uneven report times and a
// constant acceleration, which the second difference cancels), and the alignment with the test's
// answer against the alignment with the lag terms forced on and off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "kernels/core/local_track_rows.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/report_whiteness.hpp"

namespace trackassoc {
namespace {

// The test over sensor 0 of a table that holds only sensor 0: its rows grouped by track in time
// order (kernels/core/local_track_rows.hpp), as align_tracks groups them.
ReportWhiteness whiteness(const TrackTable& t, const AlignmentOptions& o = {}) {
  const LocalTrackRows g = local_track_rows(t);
  return measure_report_whiteness(t, g.row, g.start, o);
}

// Three reports at 0, 1 and 3 s (r = 2) with velocities v₀, v₁, v₂ and velocity covariances P0, P1,
// P2 (positions (0, 0), variance 100).
void push_triple(TrackTable& t, int track, const Eigen::Vector2d v[3], const Eigen::Matrix2d P[3],
                 const double times[3]) {
  for (int i = 0; i < 3; ++i) {
    Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
    C.topLeftCorner<2, 2>() = 100.0 * Eigen::Matrix2d::Identity();
    C.bottomRightCorner<2, 2>() = P[i];
    t.push_back(0, track, times[i], Eigen::Vector4d(0, 0, v[i][0], v[i][1]), C, track);
  }
}

TEST(ReportWhiteness, TheRatioIsTheHandCalculation) {
  // 30 tracks with the same triple: v = (0, 0), (1, 0), (4, 1), so e = v₂ − v₁ − r(v₁ − v₀) = (1, 1),
  // |e|² = 2; P_v = I, 2I and [3 1; 1 3], so S = P2 + (1 + r)² P1 + r² P0 = [3 1; 1 3] + 18 I + 4 I
  // = [25 1; 1 25], tr S = 50: ρ = 2/50 = 0.04, relative to med(χ²₂)/2 = ln 2: 0.04/ln 2 = 0.057708.
  // (The weights the wrong way round, 4·P2 + 9·P1 + P0, would give tr 62.)
  const Eigen::Vector2d v[3] = {{0, 0}, {1, 0}, {4, 1}};
  Eigen::Matrix2d P[3] = {Eigen::Matrix2d::Identity(), 2.0 * Eigen::Matrix2d::Identity(), {}};
  P[2] << 3, 1, 1, 3;
  const double times[3] = {0.0, 1.0, 3.0};
  TrackTable t;
  for (int k = 0; k < 30; ++k) push_triple(t, k, v, P, times);
  const ReportWhiteness w = whiteness(t);
  EXPECT_EQ(w.triples, 30u);
  EXPECT_NEAR(w.median_ratio, 0.04 / std::log(2.0), 1e-9);
  EXPECT_TRUE(w.filtered);
  // Triples that cannot be used are left out: equal times, r = 11 > 10, a zero covariance (tr S not
  // > 0), a NaN velocity. The 30 above are still all there is.
  const double equal[3] = {0.0, 0.0, 1.0}, far[3] = {0.0, 1.0, 12.0};
  push_triple(t, 100, v, P, equal);
  push_triple(t, 101, v, P, far);
  const Eigen::Matrix2d zero[3] = {Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero()};
  push_triple(t, 102, v, zero, times);
  const Eigen::Vector2d nan[3] = {{0, 0}, {std::nan(""), 0}, {4, 1}};
  push_triple(t, 103, nan, P, times);
  EXPECT_EQ(whiteness(t).triples, 30u);
  EXPECT_NEAR(whiteness(t).median_ratio, 0.04 / std::log(2.0), 1e-9);
  // 29 triples: too few to tell, the lag terms stay on.
  TrackTable s;
  const Eigen::Matrix4d C = Eigen::Vector4d(100, 100, 1, 1).asDiagonal();
  for (int k = 0; k < 31; ++k) s.push_back(0, 0, k, Eigen::Vector4d(0, 0, k % 2 ? 5.0 : -5.0, 0), C, 0);
  EXPECT_EQ(whiteness(s).triples, 0u);
  EXPECT_TRUE(whiteness(s).filtered);
}

// Beyond kMaxTriples the sample is spread over every position of the tracks. 4 096 tracks of 5
// reports, 1 s apart, have 12 288 triples; every third triple (the first of each track) would hold
// only the first. Each track's first velocity is off by 10 m/s, so its first triple has ρ = 100/12
// (|e|² = 100, tr S = 12) and the other two ρ = 0: a sample spread over the positions has
// median 0.
TEST(ReportWhiteness, TheSampleCoversEveryPositionOfTheTracks) {
  TrackTable t;
  const Eigen::Matrix4d C = Eigen::Vector4d(100, 100, 1, 1).asDiagonal();
  for (int k = 0; k < 4096; ++k)
    for (int i = 0; i < 5; ++i) t.push_back(0, k, i, Eigen::Vector4d(0, 0, i == 0 ? 10.0 : 0.0, 0), C, k);
  const ReportWhiteness w = whiteness(t);
  EXPECT_EQ(w.triples, kMaxTriples);
  EXPECT_EQ(w.median_ratio, 0.0);
  EXPECT_TRUE(w.filtered);
}

// 40 targets of sensor 0, 200 reports each at uneven times (0.5–1.5 s apart), accelerating at a
// constant (1.0, −0.6) m/s². Reported either by a CV Kalman filter per axis (σ_a = 0.5 m/s², σ_r =
// 10 m: τ ≈ 4 s) or as the truth plus independent errors of a stated covariance.
TrackTable simulated(bool filtered, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> gap(0.5, 1.5);
  TrackTable t;
  const double qa = 0.5, sr = 10.0, ax[2] = {1.0, -0.6};
  for (int id = 0; id < 40; ++id) {
    double time = 0.0, pos[2] = {0.0, 0.0}, vel[2] = {10.0, 5.0};
    Eigen::Vector2d x[2];
    Eigen::Matrix2d Pf[2];
    for (int c = 0; c < 2; ++c) {
      x[c] = Eigen::Vector2d(pos[c], vel[c]);
      Pf[c] = Eigen::Vector2d(sr * sr, 4.0).asDiagonal();
    }
    for (int k = 0; k < 200; ++k) {
      const double dt = k == 0 ? 0.0 : gap(rng);
      time += dt;
      Eigen::Vector4d state;
      Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
      for (int c = 0; c < 2; ++c) {
        pos[c] += vel[c] * dt + 0.5 * ax[c] * dt * dt;
        vel[c] += ax[c] * dt;
        if (filtered) {
          Eigen::Matrix2d F;
          F << 1, dt, 0, 1;
          Eigen::Matrix2d Q;
          Q << dt * dt * dt / 3, dt * dt / 2, dt * dt / 2, dt;
          x[c] = F * x[c];
          Pf[c] = F * Pf[c] * F.transpose() + qa * qa * Q;
          const double S = Pf[c](0, 0) + sr * sr;
          const Eigen::Vector2d K = Pf[c].col(0) / S;
          x[c] += K * (pos[c] + sr * n01(rng) - x[c](0));
          Pf[c] -= K * Pf[c].row(0);
          state[c] = x[c](0), state[2 + c] = x[c](1);
          P(c, c) = Pf[c](0, 0), P(2 + c, 2 + c) = Pf[c](1, 1), P(c, 2 + c) = P(2 + c, c) = Pf[c](0, 1);
        } else {
          state[c] = pos[c] + 15.0 * n01(rng), state[2 + c] = vel[c] + 1.0 * n01(rng);
          P(c, c) = 225.0, P(2 + c, 2 + c) = 1.0;
        }
      }
      t.push_back(0, id, time, state, P, id);
    }
  }
  return t;
}

TEST(ReportWhiteness, AFiltersOutputIsFilteredAndIndependentReportsAreNot) {
  const ReportWhiteness f = whiteness(simulated(true, 1)), w = whiteness(simulated(false, 2));
  EXPECT_EQ(f.triples, kMaxTriples);  // 40 · 198 = 7 920 triples, sampled
  EXPECT_TRUE(f.filtered);
  EXPECT_LT(f.median_ratio, 0.3);  // measured 0.06 (τ ≈ 4 s)
  EXPECT_FALSE(w.filtered);
  // Independent errors: the median of χ²₂/2 over 4 096 triples, relative to its own: 1 within its
  // sampling error (≈ 0.025), though the targets accelerate at 1.17 m/s² (the second difference
  // cancels a constant acceleration, at uneven report times too).
  EXPECT_NEAR(w.median_ratio, 1.0, 0.1);
  AlignmentOptions all;
  all.whiteness_threshold = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(whiteness(simulated(false, 2), all).filtered);
  all.whiteness_threshold = 0.0;
  EXPECT_THROW(all.validate(), InputError);
  all.whiteness_threshold = std::nan("");
  EXPECT_THROW(all.validate(), InputError);
}

// The alignment applies the test's answer: the same covariances as with the lag terms forced on
// (filtered) or off (independent).
TEST(ReportWhiteness, TheAlignmentUsesTheLagTermsOnlyForAFiltersOutput) {
  std::vector<double> times(100);
  std::iota(times.begin(), times.end(), 10.0);
  AlignmentOptions on;
  on.whiteness_threshold = std::numeric_limits<double>::infinity();
  AlignmentOptions off = on;
  off.lag_inflation = off.lag_look_ahead = 0.0;
  for (bool filtered : {true, false}) {
    const TrackTable t = simulated(filtered, 3);
    const AlignedTracks x = align_tracks(t, 0, times, AlignmentOptions{});
    const AlignedTracks same = align_tracks(t, 0, times, filtered ? on : off);
    const AlignedTracks other = align_tracks(t, 0, times, filtered ? off : on);
    EXPECT_EQ(x.cov, same.cov) << filtered;
    EXPECT_NE(x.cov, other.cov) << filtered;  // the terms do widen these tracks
  }
}

}  // namespace
}  // namespace trackassoc
