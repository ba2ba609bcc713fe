// The manoeuvre-lag terms of the two-sided alignment (kernels/statistics/association_statistic.hpp,
// AlignmentOptions: lag_inflation, lag_look_ahead, lag_noise_margin), worked out by hand on one
// track whose velocity steps at 5.5 s. Its 19 triples of reports are fewer than the whiteness test
// needs (kLeastTriples, kernels/statistics/report_whiteness.hpp), so the terms apply whatever its
// velocities.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {
namespace {

// Reports every 1 s from 0 to 20 s; P = diag(100, 100, 1, 1), so τ² = P_pp/P_vv = 100 and τ = 10 s.
// v = (10, 0) up to 5 s, (10, 4) from 6 s. Aligned at the report times (Δt = 0: no prediction).
AlignedTracks aligned(const AlignmentOptions& o) {
  TrackTable t(StateLayout::kXY_VXVY);
  const Eigen::Matrix4d P = Eigen::Vector4d(100, 100, 1, 1).asDiagonal();
  std::vector<double> times;
  for (int k = 0; k <= 20; ++k) {
    t.push_back(0, 7, k, Eigen::Vector4d(10.0 * k, 0, 10, k >= 6 ? 4 : 0), P, 1);
    times.push_back(k);
  }
  return align_tracks(t, 0, times, o);
}

double var(const AlignedTracks& x, int k, int axis) {  // the aligned variance of one state axis
  return x.cov[static_cast<std::size_t>(k) * packed_size(4) + packed_index(4, axis, axis)];
}

TEST(ManoeuvreLag, TermsMatchTheHandCalculation) {
  const AlignmentOptions o;  // lag_inflation k = 0.5, lag_look_ahead h = 1.1, lag_noise_margin 1.5
  const AlignedTracks x = aligned(o);
  // |Δv|² = 16 for any pair across the step; its noise 1.5 · tr(P_v,i + P_v,j) = 1.5 · 4 = 6: 10.
  // At 0 s: the neighbours (0 s, 1 s) do not change (current term 0); looking ahead τ = 10 s
  // crosses the step: h² · 10 = 12.1 on the velocity, 12.1 · τ² = 1210 on the position.
  EXPECT_NEAR(var(x, 0, 0), 100.0 + 1210.0, 1e-9);
  EXPECT_NEAR(var(x, 0, 2), 1.0 + 12.1, 1e-9);
  // At 5 s: the neighbours 4 s and 6 s, â² = 10 / 2² = 2.5, k² â² = 0.625: 0.625 · τ⁴ = 6250 on the
  // position and 0.625 · τ² = 62.5 on the velocity; the look-ahead as at 0 s.
  EXPECT_NEAR(var(x, 5, 1), 100.0 + 6250.0 + 1210.0, 1e-9);
  EXPECT_NEAR(var(x, 5, 3), 1.0 + 62.5 + 12.1, 1e-9);
  // At 10 s the velocity no longer changes, before or ahead: nothing is added.
  EXPECT_NEAR(var(x, 10, 0), 100.0, 1e-9);
  EXPECT_NEAR(var(x, 10, 3), 1.0, 1e-9);
}

TEST(ManoeuvreLag, TheNoiseMarginAndTheFactorsSwitchTheTermsOff) {
  AlignmentOptions o;
  o.lag_noise_margin = 4.0;  // 16 − 4 · 4 = 0: a change within its noise widens nothing
  EXPECT_NEAR(var(aligned(o), 5, 0), 100.0, 1e-9);
  o = AlignmentOptions{};
  o.lag_look_ahead = 0.0;  // the current term alone
  EXPECT_NEAR(var(aligned(o), 5, 0), 100.0 + 6250.0, 1e-9);
  EXPECT_NEAR(var(aligned(o), 0, 0), 100.0, 1e-9);
  o.lag_inflation = 0.0;
  EXPECT_NEAR(var(aligned(o), 5, 0), 100.0, 1e-9);
  o = AlignmentOptions{};
  o.method = AlignmentMethod::kForward;  // forward prediction has no lag terms
  EXPECT_NEAR(var(aligned(o), 5, 0), 100.0, 1e-9);
  o = AlignmentOptions{};
  o.lag_noise_margin = -1.0;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace trackassoc
