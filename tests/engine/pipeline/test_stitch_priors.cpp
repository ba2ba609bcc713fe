// Fragment stitching's priors on hand-made files (tests/support/stitching_files.hpp): the gap prior
// learnt from the first joins and the start-state density of "a different target", each against a
// hand-computed ratio (engine/pipeline/track_stitching.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "engine/pipeline/stitch_join_cost.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "kernels/statistics/chi_square.hpp"
#include "tests/support/stitching_files.hpp"

namespace trackassoc {
namespace {

using namespace stitching_test;

// The gap prior (gap_bin_s = 20): 40 handovers with a gap of 20 s (far apart: lanes 200 km apart
// along y, nothing else gated) and one weak join C → D over 150 s. Without the prior every gated
// join of positive evidence is made (41). With it, the first joins' gaps give the bins (width
// 20 s from −2 s: W = 182 s, 10 bins, the last 2 s wide) Laplace counts 41 (gap 20 s, bin 1) and
// 2 (gap 150 s, bin 7) of 51, so the weak join's ratio is multiplied by W·2/(51·20) = 0.3569,
// −1.0304 nats: a join of 1.00 nat is refused and one of 1.06 nats is kept.
TrackStitchSummary weak_long_join(double evidence, double gap_bin_s, AssociationRecord& rec) {
  std::vector<Segment> segments;
  std::vector<std::pair<int32_t, int32_t>> keys;
  for (int32_t i = 0; i < 40; ++i) {
    segments.push_back({0, i, 0, 40, 0, 200, 2e5 * i, 0});
    segments.push_back({1, 100 + i, 60, 100, 0, 200, 2e5 * i, 0});
    keys.push_back({0, i});
    keys.push_back({1, 100 + i});
  }
  // The box of the start states: x over [0, 1e6] (the background's start), y over [−2e5, 1e7],
  // the velocities all (200, 0); C's window [38, 220] s holds n = 41 starts (the 40 B's and D).
  const double tau = 75.0, s_pos = 2.0 * (1e4 + tau * tau);  // per axis S = diag(s_pos, 2)
  const double log_det = kLog2Pi4 + 2.0 * std::log(s_pos * 2.0);
  const double log_alternative = std::log(1e6) + std::log(1.02e7) - std::log(41.0);
  const double m2 = 2.0 * (log_alternative - evidence) - log_det;  // −c = evidence
  const double delta = std::sqrt(m2 * s_pos);
  segments.push_back({0, 200, 0, 40, 0, 200, -2e5, 0});         // C
  segments.push_back({1, 201, 190, 230, delta, 200, -2e5, 0});  // D, 150 s after C's end
  segments.push_back({1, 300, 0, 400, 1e6, 200, 1e7, 0});       // background, coexisting
  keys.push_back({0, 200});
  keys.push_back({1, 201});
  keys.push_back({1, 300});
  const TrackFile f = hand_made(segments);
  rec = singletons(keys);
  TrackStitchOptions o = no_manoeuvre();
  o.gap_bin_s = gap_bin_s;
  o.start_density_bins = false;  // the box density of the hand calculation
  return stitch_fragments(f, rec, o);
}

TEST(TrackStitching, TheGapPriorRefusesAWeakJoinAtAGapTheOtherJoinsDoNotHave) {
  AssociationRecord rec;
  EXPECT_EQ(weak_long_join(1.00, 0.0, rec).stitches, 41);  // no prior: every positive join
  EXPECT_EQ(rec.target[81], rec.target[80]);
  EXPECT_EQ(weak_long_join(1.00, 20.0, rec).stitches, 40);  // 1.00 − 1.0304 < 0
  EXPECT_NE(rec.target[81], rec.target[80]);
  EXPECT_EQ(rec.target[1], rec.target[0]);                  // the handovers stay joined
  EXPECT_EQ(weak_long_join(1.06, 20.0, rec).stitches, 41);  // 1.06 − 1.0304 > 0
  EXPECT_EQ(rec.target[81], rec.target[80]);
}

// The start density (start_density_bins). A ends at 40 s, B starts at 60 s δ ahead along x (same
// velocity); two coexisting background tracks start at (0, 3 km) with vx = −300 and 2 200 m/s (a
// wild first velocity that stretches the box). Start states, G = 4, B = ⌈√4⌉ = 2 bins a component;
// B is scored against the histogram of the other three starts (leave-one-out,
// kernels/statistics/histogram_density.hpp), G − 1 + B = 5: x {0, 12 km + δ, 0, 0}: B alone in the
// upper bin, h = 1/(5·w/2) against the box's 1/w (ratio 2/5); y {0, 0, 3 km, 3 km}: one other in
// B's bin, ratio 2·2/5 = 4/5; vx {200, 200, −300, 2200} over 2 500 m/s: two others in B's bin, ratio
// 3·2/5 = 6/5; vy all 0, w = 1: three others, ratio 4·2/5 = 8/5. So the histogram adds
// ln(2/5 · 4/5 · 6/5 · 8/5) = −ln(625/384) ≈ −0.4871 nats to the box's cost: B starts where no other
// start is, so "a different target" explains it worse than the box says. A join of evidence −0.20 or
// −0.47 nats under the box (refused there) is made, one of −0.50 is refused. (Counting B in its own
// bins, as before session 28, added +ln(40/27) ≈ 0.3930 nats: B's own count made its start look
// common, and the join of −0.20 was refused.)
int density_join(double evidence, bool bins) {
  // Box: c = ½(m² + ln det(2πS)) + ln n − ln V, n = 1, V = (12 km + δ)·3 km·2 500·1; δ by fixed point.
  double delta = 650.0;
  for (int i = 0; i < 50; ++i) {
    const double log_v = std::log(12000.0 + delta) + std::log(3000.0) + std::log(2500.0);
    delta = std::sqrt(20200.0 * 2.0 * (log_v - 0.5 * kLogDet20 - evidence));
  }
  EXPECT_LT(m2_of_offset(delta), kGate);
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200},
                                 {1, 7, 60, 100, delta, 200},
                                 {1, 98, 0, 200, 0, -300, 3000, 0},
                                 {0, 97, 0, 200, 0, 2200, 3000, 0}});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 98}, {0, 97}});
  TrackStitchOptions o = no_manoeuvre();
  o.gap_bin_s = 0.0;
  o.start_density_bins = bins;
  const TrackStitchSummary s = stitch_fragments(f, rec, o);
  EXPECT_EQ(s.candidates, 1);
  return s.stitches;
}

TEST(TrackStitching, TheDensityOfTheOtherStartsMakesAJoinThatTheBoxRefuses) {
  EXPECT_NEAR(std::log(625.0 / 384.0), 0.4871, 1e-4);
  EXPECT_EQ(density_join(-0.20, false), 0);  // the box: −0.20 nats, refused
  EXPECT_EQ(density_join(-0.20, true), 1);   // −0.20 + 0.487 > 0
  EXPECT_EQ(density_join(-0.47, true), 1);   // −0.47 + 0.487 > 0
  EXPECT_EQ(density_join(-0.50, true), 0);   // −0.50 + 0.487 < 0
}

}  // namespace
}  // namespace trackassoc
