// The whiteness test that decides whether a sensor's reports are a filter's output, so that the
// alignment's lag terms apply (kernels/statistics/manoeuvre_lag.hpp): a hand-calculated ratio, a
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

#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/manoeuvre_lag.hpp"

namespace trackassoc {
namespace {

// The rows of `sensor`, ordered by (track, time), and the first of each track's, as align_tracks
// groups them.
struct Grouped {
  std::vector<std::size_t> rows, begin;
};
Grouped group(const TrackTable& t, int32_t sensor) {
  Grouped g;
  for (std::size_t r = 0; r < t.size(); ++r)
    if (t.sensor[r] == sensor) g.rows.push_back(r);
  std::stable_sort(g.rows.begin(), g.rows.end(), [&](std::size_t x, std::size_t y) {
    return t.track[x] != t.track[y] ? t.track[x] < t.track[y] : t.t[x] < t.t[y];
  });
  for (std::size_t q = 0; q < g.rows.size(); ++q)
    if (q == 0 || t.track[g.rows[q]] != t.track[g.rows[q - 1]]) g.begin.push_back(q);
  g.begin.push_back(g.rows.size());
  return g;
}

ReportWhiteness whiteness(const TrackTable& t, int32_t sensor, const AlignmentOptions& o = {}) {
  const Grouped g = group(t, sensor);
  return sensor_reports_are_filtered(t, g.rows, g.begin, o);
}

TEST(ReportWhiteness, TheRatioIsTheHandCalculation) {
  // 30 tracks with the same three reports at 0, 1 and 3 s (r = 2), P_v = I: v = (0, 0), (1, 0),
  // (4, 1). e = v₂ − v₁ − r(v₁ − v₀) = (1, 1), |e|² = 2; the noise 2·(1 + 3² + 2²) = 28;
  // ρ = 1/14, relative to med(χ²₂)/2 = ln 2: 1/(14 ln 2) = 0.10305.
  TrackTable t;
  const Eigen::Matrix4d P = Eigen::Vector4d(100, 100, 1, 1).asDiagonal();
  for (int k = 0; k < 30; ++k) {
    t.push_back(0, k, 0.0, Eigen::Vector4d(0, 0, 0, 0), P, k);
    t.push_back(0, k, 1.0, Eigen::Vector4d(0, 0, 1, 0), P, k);
    t.push_back(0, k, 3.0, Eigen::Vector4d(0, 0, 4, 1), P, k);
  }
  const ReportWhiteness w = whiteness(t, 0);
  EXPECT_EQ(w.triples, 30u);
  EXPECT_NEAR(w.median_ratio, 1.0 / (14.0 * std::log(2.0)), 1e-6);
  EXPECT_TRUE(w.filtered);
  // 29 triples: too few to tell, the lag terms stay on.
  TrackTable s;
  for (int k = 0; k < 31; ++k) s.push_back(0, 0, k, Eigen::Vector4d(0, 0, k % 2 ? 5.0 : -5.0, 0), P, 0);
  EXPECT_EQ(whiteness(s, 0).triples, 0u);
  EXPECT_TRUE(whiteness(s, 0).filtered);
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
  const ReportWhiteness f = whiteness(simulated(true, 1), 0), w = whiteness(simulated(false, 2), 0);
  EXPECT_EQ(f.triples, 40u * 198u / 2);  // every second triple: 7 920 > kMaxTriples
  EXPECT_TRUE(f.filtered);
  EXPECT_LT(f.median_ratio, 0.3);  // measured 0.06 (τ ≈ 4 s)
  EXPECT_FALSE(w.filtered);
  // Independent errors: the median of χ²₂/2 over 3 960 triples, relative to its own: 1 within its
  // sampling error (≈ 0.025), though the targets accelerate at 1.17 m/s² (the second difference
  // cancels a constant acceleration, at uneven report times too).
  EXPECT_NEAR(w.median_ratio, 1.0, 0.1);
  AlignmentOptions all;
  all.unfiltered_ratio = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(whiteness(simulated(false, 2), 0, all).filtered);
  all.unfiltered_ratio = 0.0;
  EXPECT_THROW(all.validate(), InputError);
  all.unfiltered_ratio = std::nan("");
  EXPECT_THROW(all.validate(), InputError);
}

// The alignment applies the test's answer: the same covariances as with the lag terms forced on
// (filtered) or off (independent).
TEST(ReportWhiteness, TheAlignmentUsesTheLagTermsOnlyForAFiltersOutput) {
  std::vector<double> times(100);
  std::iota(times.begin(), times.end(), 10.0);
  AlignmentOptions on;
  on.unfiltered_ratio = std::numeric_limits<double>::infinity();
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
