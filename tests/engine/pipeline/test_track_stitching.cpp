// Fragment stitching by track segment association (engine/pipeline/track_stitching.hpp) on
// hand-made files: every cost below is worked out by hand from the closed form of the midpoint
// prediction (for reports with diagonal P and equal halves of the gap, the forward and backward
// cross terms cancel, so S is diagonal), and the joins are checked against the assignment that
// those costs imply.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

struct Segment {
  int32_t sensor = 0, track = 0;
  double t0 = 0, t1 = 0, x0 = 0, vx = 0, y0 = 0, vy = 0;  // position at t = 0 and velocity
};

// Two sensors (ids 0, 1), reports every 2 s on each segment, P = diag(100², 100², 1, 1).
TrackFile hand_made(const std::vector<Segment>& segments) {
  TrackFile f;
  for (int32_t id : {0, 1}) {
    Sensor s;
    s.id = id;
    f.sensors.push_back(s);
  }
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  for (const auto& g : segments)
    for (double t = g.t0; t <= g.t1 + 1e-9; t += 2.0)
      f.tracks.push_back(g.sensor, g.track, t, Eigen::Vector4d(g.x0 + g.vx * t, g.y0 + g.vy * t, g.vx, g.vy),
                         P, -1);
  return f;
}

// A far target that coexists with everything (never a candidate) and spans the "different
// targets" box: its start (−60 km, −60 km, −300 m/s, −300 m/s).
const Segment kBackground{1, 99, 0, 200, -60000, -300, -60000, -300};

// One tuple of one member per (sensor, track) given, target numbers 0, 1, ...
AssociationRecord singletons(const std::vector<std::pair<int32_t, int32_t>>& keys) {
  AssociationRecord rec;
  rec.num_sensors = 2;
  for (const auto& [sensor, track] : keys) {
    rec.tuples.push_back(sensor == 0 ? track : -1);
    rec.tuples.push_back(sensor == 1 ? track : -1);
    rec.target.push_back(static_cast<int32_t>(rec.target.size()));
  }
  return rec;
}

// The quiet model alone with σ_a = 0 (and the gate on it).
TrackStitchOptions no_manoeuvre() {
  TrackStitchOptions o;
  o.manoeuvre_sigma = o.turn_sigma = 0.0;
  o.turn_probability = 0.0;
  return o;
}

const double kGate = chi_square_quantile(0.9999, 4);  // χ²₄(0.9999) ≈ 23.51
const double kLog2Pi4 = 4.0 * std::log(2.0 * std::numbers::pi);

// By hand, σ_a = 0, a gap of 20 s (each end predicted 10 s to the midpoint): along x the forward
// prediction is [[1e4 + 100, 10], [10, 1]], the backward one [[1e4 + 100, −10], [−10, 1]], so
// S = diag(20200, 2) along x and (both y states 0 in these files) S = diag(20200, 2) along y too.
// A start displaced by δ along x (same velocity) gives m² = δ²/20200, and
// ln det(2πS) = 4 ln 2π + 2 ln(20200·2).
double m2_of_offset(double delta) { return delta * delta / 20200.0; }
const double kLogDet20 = kLog2Pi4 + 2.0 * std::log(20200.0 * 2.0);
double critical_offset() { return std::sqrt(20200.0 * kGate); }

// ln V of the box of the start states, by hand from the segments' start states.
double log_volume(const std::vector<std::array<double, 4>>& starts) {
  double v = 0.0;
  for (int i = 0; i < 4; ++i) {
    double lo = 1e300, hi = -1e300;
    for (const auto& s : starts) lo = std::min(lo, s[i]), hi = std::max(hi, s[i]);
    v += std::log(std::max(hi - lo, 1.0));
  }
  return v;
}

TEST(TrackStitching, TheMidpointStatisticIsSymmetricAndEqualsTheForwardOne) {
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 300, 200}});
  // Rows 0..20 are track 1 (0-40 s), row 20 its end; row 21 track 7's start at 60 s.
  const GapStatistic g = gap_statistic(f.tracks, 20, 21, 0.0);
  EXPECT_NEAR(g.m2, m2_of_offset(300.0), 1e-9);
  EXPECT_NEAR(g.log_det, kLogDet20, 1e-9);
  EXPECT_NEAR(g.m2, continuation_statistic(f.tracks, 20, 21, 0.0), 1e-9);
  EXPECT_NEAR(gap_statistic(f.tracks, 20, 21, 9.0).m2, continuation_statistic(f.tracks, 20, 21, 9.0), 1e-9);
}

TEST(TrackStitching, AHandoverInsideTheHandComputedGateIsJoined) {
  const double delta = 0.95 * critical_offset();
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, delta, 200}, kBackground});
  // Its cost: ½ m² + ½ ln det(2πS) − ln V < 0 (positive evidence).
  const double lv = log_volume({{0, 0, 200, 0}, {delta + 12000, 0, 200, 0}, {-60000, -60000, -300, -300}});
  EXPECT_LT(0.5 * (m2_of_offset(delta) + kLogDet20) - lv, 0.0);
  EXPECT_NEAR(join_cost(f.tracks, 20, 21, no_manoeuvre(), kGate), 0.5 * (m2_of_offset(delta) + kLogDet20),
              1e-9);
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.groups, 3);
  EXPECT_EQ(s.candidates, 1);
  EXPECT_EQ(s.stitches, 1);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 0, 2}));  // the later group takes the earlier one's number
}

TEST(TrackStitching, AHandoverJustOutsideTheGateIsKeptApart) {
  const TrackFile f =
      hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 1.05 * critical_offset(), 200}, kBackground});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.candidates, 0);
  EXPECT_EQ(s.stitches, 0);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 2}));
}

TEST(TrackStitching, WithoutEvidenceAgainstDifferentTargetsNothingIsJoined) {
  // The same handover alone: the box of the two starts is 12 km × 1 × 1 × 1, so
  // ln V = ln(12000) ≈ 9.39 < ½ ln det(2πS) ≈ 14.28: the join is gated but a start anywhere in so
  // small a scene is as likely; no evidence, no join.
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 0, 200}});
  EXPECT_GT(0.5 * kLogDet20 - std::log(12000.0), 0.0);
  AssociationRecord rec = singletons({{0, 1}, {1, 7}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.candidates, 1);
  EXPECT_EQ(s.stitches, 0);
}

TEST(TrackStitching, OfTwoSuccessorsTheBetterIsJoined) {
  // Offsets 0.3 and 0.5 of the critical one: m² = 0.09 and 0.25 of the gate; equal det and V, so
  // the nearer is cheaper and the one assignment takes it.
  const double d = critical_offset();
  const TrackFile f = hand_made(
      {{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 0.5 * d, 200}, {1, 8, 60, 100, -0.3 * d, 200}, kBackground});
  // Without the swap margin (engine/pipeline/stitch_swap_margin.hpp) the one assignment takes it.
  TrackStitchOptions o = no_manoeuvre();
  o.swap_margin = 0.0;
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 8}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, o);
  EXPECT_EQ(s.candidates, 2);
  EXPECT_EQ(s.stitches, 1);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 0, 3}));
  // With it (3.5 nats by default) the join is left unmade: the other start is worse by only
  // ½(0.25 − 0.09)·χ²₄(0.9999) = 1.88 nats of the gap statistic (the same gap, so the same gap
  // prior), too close to tell which successor is the target's.
  EXPECT_LT(0.5 * (0.25 - 0.09) * kGate, no_manoeuvre().swap_margin);
  AssociationRecord ambiguous = singletons({{0, 1}, {1, 7}, {1, 8}, {1, 99}});
  EXPECT_EQ(stitch_fragments(f, ambiguous, no_manoeuvre()).stitches, 0);
}

TEST(TrackStitching, OneAssignmentJoinsACrossingThatTheGreedyAndTheMutualRulesMiss) {
  // Ends A1 (sensor 0 track 1) and A2 (track 2) at 40 s, starts B1 (sensor 1 track 7) and B2
  // (track 8) at 60 s, all at 200 m/s along x. At the midpoint (50 s) A1 and B1 meet at x = 10 km,
  // B2 is 500 m ahead, A2 500 m behind: m²(A1,B1) = 0, m²(A1,B2) = m²(A2,B1) = 500²/20200 ≈ 12.38,
  // m²(A2,B2) = 1000²/20200 ≈ 49.5 > the gate. With k = ½ ln det(2πS) − ln V + ln 2 (B1 and B2 are
  // the n = 2 starts of each end's window) the same for every
  // pair: greedy (cheapest first) takes A1–B1 (k) and leaves A2 with nothing; the mutual rule of
  // before joined nothing (A1's two successors coexist); the assignment takes A1–B2 and A2–B1,
  // 12.38 + 2k < k since k < −12.38 here.
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200},
                                 {0, 2, 0, 40, -500, 200},
                                 {1, 7, 60, 100, 0, 200},
                                 {1, 8, 60, 100, 500, 200},
                                 kBackground});
  const double lv = log_volume({{0, 0, 200, 0},
                                {-500, 0, 200, 0},
                                {12000, 0, 200, 0},
                                {12500, 0, 200, 0},
                                {-60000, -60000, -300, -300}});
  const double k = 0.5 * kLogDet20 - lv + std::log(2.0);
  EXPECT_LT(2.0 * 0.5 * m2_of_offset(500.0) + 2.0 * k, k);  // the crossing beats A1–B1 alone
  EXPECT_GT(m2_of_offset(1000.0), kGate);                   // A2–B2 is not a candidate
  AssociationRecord rec = singletons({{0, 1}, {0, 2}, {1, 7}, {1, 8}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.candidates, 3);
  EXPECT_EQ(s.stitches, 2);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 1, 0, 4}));  // A1 = B2, A2 = B1
}

// A 90° turn during a 60 s gap: A runs along +x at 200 m/s from x = 0 (0-40 s), turns at the
// midpoint (70 s, x = 14 km) and B runs along +y from there (100-160 s, starting at (14 km, 6 km)).
// Each end predicted τ = 30 s to the midpoint, per axis S = diag(2(1e4 + τ² + qτ³/3), 2(1 + qτ));
// the positions meet at the corner, the velocities differ by (200, −200):
//   quiet (σ_a = 3): S = diag(183800, 542) per axis, m² = 2·200²/542 ≈ 147.6 > the gate (refused,
//   as the CV gate with σ_a = 3 of before: continuation_statistic gives the same m²);
//   turn (σ_a = 20): S = diag(7221800, 24002) per axis, m² = 2·200²/24002 ≈ 3.33.
struct Turn {
  double m2_quiet = 2.0 * 200.0 * 200.0 / 542.0, m2_turn = 2.0 * 200.0 * 200.0 / 24002.0;
  double log_det_quiet = kLog2Pi4 + 2.0 * std::log(183800.0 * 542.0);
  double log_det_turn = kLog2Pi4 + 2.0 * std::log(7221800.0 * 24002.0);
  // −ln[(1 − π) N_quiet + π N_turn], π = 0.2
  double cost() const {
    return -std::log(0.8 * std::exp(-0.5 * (m2_quiet + log_det_quiet)) +
                     0.2 * std::exp(-0.5 * (m2_turn + log_det_turn)));
  }
};

TEST(TrackStitching, ATurnDuringTheGapIsBridgedByTheManoeuvringModel) {
  const TrackFile f =
      hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 100, 160, 14000, 0, 6000 - 200 * 100, 200}, kBackground});
  const Turn turn;
  TrackStitchOptions defaults;
  defaults.start_density_bins = false;  // the box density of the hand calculation
  EXPECT_NEAR(continuation_statistic(f.tracks, 20, 21, 9.0), turn.m2_quiet, 1e-6);
  EXPECT_GT(turn.m2_quiet, kGate);
  EXPECT_NEAR(gap_statistic(f.tracks, 20, 21, 400.0).m2, turn.m2_turn, 1e-9);
  EXPECT_NEAR(join_cost(f.tracks, 20, 21, defaults, kGate), turn.cost(), 1e-9);
  double d = 0.0;  // ln N_turn − ln N_quiet
  join_cost(f.tracks, 20, 21, defaults, kGate, &d);
  EXPECT_NEAR(d, 0.5 * (turn.m2_quiet + turn.log_det_quiet) - 0.5 * (turn.m2_turn + turn.log_det_turn), 1e-9);
  const double lv = log_volume({{0, 0, 200, 0}, {14000, 6000, 0, 200}, {-60000, -60000, -300, -300}});
  // Positive evidence, ≈ 34.74 − 32.83 = 1.91 nats (B is the only start of A's window: n = 1), though
  // only the manoeuvring model gates it: joined.
  EXPECT_LT(turn.cost() - lv, 0.0);
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, defaults);
  EXPECT_EQ(s.stitches, 1);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 0, 2}));
  // The weight learnt from that one join: its responsibility under the turn model is 1 − O(e^−60),
  // so π̂ = (1 + 10 · 0.2) / (1 + 10) = 3/11 (the Beta prior's 10 pseudo-joins at 0.2).
  EXPECT_GT(d, 60.0);
  EXPECT_NEAR(s.turn_probability, 3.0 / 11.0, 1e-6);
  // The quiet model alone (π = 0, gate on σ_a = 3) refuses it, as the CV gate did.
  TrackStitchOptions quiet = defaults;
  quiet.turn_sigma = quiet.manoeuvre_sigma;
  quiet.turn_probability = 0.0;
  AssociationRecord before = singletons({{0, 1}, {1, 7}, {1, 99}});
  EXPECT_EQ(stitch_fragments(f, before, quiet).stitches, 0);
}

// Straight handover k (from T = 1 000 + 400k s): 40 s on sensor 0 (track 100 + k), a gap, 60 s on
// sensor 1 (track 200 + k), on the line x = −20 km + 200 m/s (t − T), y = −20 km.
void add_straight_handover(int32_t k, double gap, std::vector<Segment>& segments,
                           std::vector<std::pair<int32_t, int32_t>>& keys) {
  const double T = 1000.0 + 400.0 * k, x0 = -20000.0 - 200.0 * T;
  segments.push_back({0, 100 + k, T, T + 40, x0, 200, -20000, 0});
  segments.push_back({1, 200 + k, T + 40 + gap, T + 100 + gap, x0, 200, -20000, 0});
  keys.push_back({0, 100 + k});
  keys.push_back({1, 200 + k});
}

TEST(TrackStitching, TheLearntWeightRefusesATurnWhereTheFileSaysTargetsFlyStraight) {
  // The turn above beside 80 straight handovers, each alone in its window (pair k from 1000 + 400k s:
  // 40 s on sensor 0, a 60 s gap, 60 s on sensor 1, on the line x = −20 km + 200 m/s (t − T_k),
  // y = −20 km: start states inside the box of the turn's test, so ln V is the same). Without the
  // gap prior (gap_bin_s = 0) and with a prior of one pseudo-join, the first assignment makes all 81
  // joins; the straight ones say "quiet" (d = −ln(7221800·24002 / (183800·542)) ≈ −7.46 at e = 0, a
  // responsibility of ~1e-5 each), the turn "manoeuvring" (d > 60, ≈ 1), so π̂ ≈ (1 + 0.2) / (81 + 1).
  // Under π̂ the turn's evidence is ≈ 1.91 − ln(0.2 / π̂) < 0 (it needs π̂ ≥ 0.2 e^−1.91 ≈ 0.0296):
  // it is left unmade, the 80 straight joins kept. With the weight fixed at 0.2 all 81 are made.
  std::vector<Segment> segments{
      {0, 1, 0, 40, 0, 200}, {1, 7, 100, 160, 14000, 0, 6000 - 200 * 100, 200}, kBackground};
  std::vector<std::pair<int32_t, int32_t>> keys{{0, 1}, {1, 7}, {1, 99}};
  for (int32_t k = 0; k < 80; ++k) add_straight_handover(k, 60.0, segments, keys);
  const TrackFile f = hand_made(segments);
  TrackStitchOptions o;
  o.start_density_bins = false;
  o.gap_bin_s = 0.0;
  o.turn_prior_joins = 1.0;
  AssociationRecord learnt = singletons(keys);
  const TrackStitchSummary s = stitch_fragments(f, learnt, o);
  const Turn turn;
  const double lv = log_volume({{0, 0, 200, 0}, {14000, 6000, 0, 200}, {-60000, -60000, -300, -300}});
  const double needed = 0.2 * std::exp(turn.cost() - lv);  // the π̂ at which the turn's evidence is 0
  EXPECT_NEAR(needed, 0.0296, 5e-4);
  EXPECT_NEAR(s.turn_probability, 1.2 / 82.0, 1e-4);
  EXPECT_LT(s.turn_probability, needed);
  EXPECT_EQ(s.stitches, 80);
  EXPECT_NE(learnt.target[0], learnt.target[1]);  // A and B apart
  for (int32_t k = 0; k < 80; ++k) EXPECT_EQ(learnt.target[3 + 2 * k], learnt.target[4 + 2 * k]);
  TrackStitchOptions fixed = o;
  fixed.learn_turn_probability = false;
  AssociationRecord given = singletons(keys);
  const TrackStitchSummary g = stitch_fragments(f, given, fixed);
  EXPECT_EQ(g.stitches, 81);
  EXPECT_EQ(g.turn_probability, 0.0);
  EXPECT_EQ(given.target[0], given.target[1]);
}

TEST(TrackStitching, TheTurnWeightGrowsWithTheGapWhereTargetsTurnDuringLongGapsOnly) {
  // 40 straight handovers across 10 s gaps (pair k from 1 000 + 400k s: 40 s on sensor 0, 60 s on
  // sensor 1, on y = −20 km at 200 m/s) and 40 turns across 60 s gaps (the turn above, from 20 000 +
  // 400k s). The first assignment (π = 0.2) makes all 80 joins; the straight ones say "quiet"
  // (responsibility ≈ 0 at span 10 s), the turns "manoeuvring" (≈ 1 at span 60 s). A constant weight
  // would be (40 + 10·0.2)/(80 + 10) ≈ 0.47 at every gap; the span model π(s) = 1 − (1 − π_c)
  // e^{−λ s} (kernels/statistics/mixture_weight.hpp) makes it grow with the gap. With the
  // responsibilities 0 and 1, ℓ(π_c, λ) = 40 ln(1 − π(10)) + 40 ln π(60) + (10/80) Σ_j [0.2 ln π(s_j)
  // + 0.8 ln(1 − π(s_j))] (the prior's 10 pseudo-joins spread over the 80 joins' spans), maximised
  // outside the engine (scipy's Nelder–Mead from a grid of starts): π_c → 0, 1/λ = 38.23 s, π(10 s)
  // = 0.230, π(35 s) = 0.600, π(60 s) = 0.792.
  std::vector<Segment> segments{kBackground};
  std::vector<std::pair<int32_t, int32_t>> keys{{1, 99}};
  for (int32_t k = 0; k < 40; ++k) {
    add_straight_handover(k, 10.0, segments, keys);
    const double U = 20000.0 + 400.0 * k;
    segments.push_back({0, 300 + k, U, U + 40, -200.0 * U, 200, 0, 0});
    segments.push_back({1, 400 + k, U + 100, U + 160, 14000, 0, 6000 - 200 * (U + 100), 200});
    keys.push_back({0, 300 + k});
    keys.push_back({1, 400 + k});
  }
  const TrackFile f = hand_made(segments);
  TrackStitchOptions o;
  o.start_density_bins = false;
  o.gap_bin_s = 0.0;
  AssociationRecord rec = singletons(keys);
  const TrackStitchSummary s = stitch_fragments(f, rec, o);
  EXPECT_EQ(s.stitches, 80);
  for (int32_t k = 0; k < 80; ++k) EXPECT_EQ(rec.target[1 + 2 * k], rec.target[2 + 2 * k]);
  EXPECT_NEAR(s.manoeuvre_interval_s, 38.23, 1.0);
  EXPECT_NEAR(s.turn_probability, 0.600, 0.01);  // π̂ at the mean span, 35 s
}

TEST(TrackStitching, ATurnJoinWithANearRivalIsLeftUnmade) {
  // The turn above, and a second start C 1 km beside B (1000²/7221800 ≈ 0.14 more m² under the turn
  // model, in its gate; outside the quiet one like B): both have positive evidence (1.91 − ln 2 ≈
  // 1.22 and 0.07 nats less), and A–B beats the exchange A–C by ≈ 0.07 nats, under the swap margin
  // (3.5): neither is joined. Without the margin the nearer start B is.
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200},
                                 {1, 7, 100, 160, 14000, 0, 6000 - 200 * 100, 200},
                                 {1, 8, 100, 160, 15000, 0, 6000 - 200 * 100, 200},
                                 kBackground});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 8}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, TrackStitchOptions{});
  EXPECT_EQ(s.candidates, 2);
  EXPECT_EQ(s.stitches, 0);
  TrackStitchOptions no_margin;
  no_margin.swap_margin = 0.0;
  AssociationRecord taken = singletons({{0, 1}, {1, 7}, {1, 8}, {1, 99}});
  EXPECT_EQ(stitch_fragments(f, taken, no_margin).stitches, 1);
  EXPECT_EQ(taken.target, (std::vector<int32_t>{0, 0, 2, 3}));
}

TEST(TrackStitching, AJumpBeyondTheManoeuvringGateIsRefused) {
  // The same turn with B 15 km further along x: the turn model adds 15000²/7221800 ≈ 31.2 to m²,
  // 34.5 > the gate.
  const TrackFile f =
      hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 100, 160, 29000, 0, 6000 - 200 * 100, 200}, kBackground});
  EXPECT_GT(Turn{}.m2_turn + 15000.0 * 15000.0 / 7221800.0, kGate);
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 99}});
  const TrackStitchSummary s = stitch_fragments(f, rec, TrackStitchOptions{});
  EXPECT_EQ(s.candidates, 0);
  EXPECT_EQ(s.stitches, 0);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 2}));
}

TEST(TrackStitching, GroupsThatCoexistAreLeftToTheAssociationAndAChainIsOneTarget) {
  // Sensor 1's track 7 reports from 30 s: it coexists with sensor 0's 0-40 s for 10 s (> 2 s).
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 30, 100, 0, 200}, kBackground});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 99}});
  EXPECT_EQ(stitch_fragments(f, rec, no_manoeuvre()).candidates, 0);
  // A chain: 0-40 s on sensor 0, 60-100 s on sensor 1, 120-160 s on sensor 0 again (a new track).
  const TrackFile g =
      hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 0, 200}, {0, 2, 120, 160, 0, 200}, kBackground});
  AssociationRecord chain = singletons({{0, 1}, {1, 7}, {0, 2}, {1, 99}});
  EXPECT_EQ(stitch_fragments(g, chain, no_manoeuvre()).stitches, 2);
  EXPECT_EQ(chain.target, (std::vector<int32_t>{0, 0, 0, 3}));
  // Off: nothing changes.
  AssociationRecord off = singletons({{0, 1}, {1, 7}, {0, 2}, {1, 99}});
  TrackStitchOptions o = no_manoeuvre();
  o.enabled = false;
  EXPECT_EQ(stitch_fragments(g, off, o).stitches, 0);
  EXPECT_EQ(off.target, (std::vector<int32_t>{0, 1, 2, 3}));
}

TEST(TrackStitching, ThePreGateRefusesOnlyPairsOutsideTheGate) {
  // Brute force: 400 random report pairs (random states, random correlated covariances, gaps of
  // −2..180 s); join_cost is finite exactly when the manoeuvring model's m² is inside the gate,
  // whatever the diagonal pre-gate refuses first. Offsets of 0-30 km put pairs on both sides.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TrackFile f;
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  for (int i = 0; i < 800; ++i) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c <= r; ++c) A(r, c) = (r == c ? 1.0 : 0.5) * (u(rng) - (r == c ? 0.0 : 0.5));
    A.diagonal().head<2>() *= 300.0;
    A.diagonal().tail<2>() *= 10.0;
    A(2, 0) *= 30.0, A(3, 1) *= 30.0;
    const Eigen::Matrix4d P = A * A.transpose() + 1e-3 * Eigen::Matrix4d::Identity();
    const double t = i % 2 == 0 ? 100.0 : 98.0 + 182.0 * u(rng);
    const Eigen::Vector4d x(3e4 * u(rng), 3e4 * u(rng), 400.0 * (u(rng) - 0.5), 400.0 * (u(rng) - 0.5));
    f.tracks.push_back(0, i, t, x, P, -1);
  }
  const TrackStitchOptions o;
  int inside = 0;
  for (std::size_t r = 0; r < 800; r += 2) {
    const double m2 = gap_statistic(f.tracks, r, r + 1, o.turn_sigma * o.turn_sigma).m2;
    EXPECT_EQ(std::isfinite(join_cost(f.tracks, r, r + 1, o, kGate)), m2 <= kGate) << r;
    inside += m2 <= kGate;
  }
  EXPECT_GT(inside, 10);  // both sides are exercised
  EXPECT_LT(inside, 390);
}

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

TEST(TrackStitching, TheStartsRepresentativeReportRefusesAJoinThatItsFirstVelocityMakes) {
  // A runs along +x at 200 m/s (0-40 s) and dies; B (a different target) starts at 60 s where A
  // would be, (12 km, 0), running along +y. B's first report has the velocity of two plots,
  // (200, 0) m/s with P_v = 300² (the rows after it: (0, 200), P = diag(100², 100², 1, 1)).
  TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, kBackground});  // rows 0-20 A, 21-121 background
  Eigen::Matrix4d P0 = Eigen::Matrix4d::Zero(), P = Eigen::Matrix4d::Zero();
  P0.diagonal() << 1e4, 1e4, 9e4, 9e4;
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  f.tracks.push_back(1, 7, 60.0, Eigen::Vector4d(12000, 0, 200, 0), P0, -1);  // row 122
  for (double t = 62.0; t <= 100.0 + 1e-9; t += 2.0)
    f.tracks.push_back(1, 7, t, Eigen::Vector4d(12000, 200 * (t - 60), 0, 200), P, -1);
  // The first report against A's end, to the midpoint 50 s: e = 0; per axis S = [[1e4 + 100 +
  // 1e4 + 100·9e4, 10 − 10·9e4], [·, 1 + 9e4]], det = 9 020 100·90 001 − 899 990² = 1 836 020 000,
  // so c = ½(4 ln 2π + 2 ln 1 836 020 000) ≈ 25.007 < ln V ≈ 34.105 (box of A, B's first report
  // and the background: 72 km · 60 km · 500 · 300 m/s): 9.1 nats for the join.
  const double c_first = 0.5 * (kLog2Pi4 + 2.0 * std::log(1836020000.0));
  EXPECT_NEAR(join_cost(f.tracks, 20, 122, no_manoeuvre(), kGate), c_first, 1e-6);
  EXPECT_LT(c_first - (std::log(72000.0) + std::log(60000.0) + std::log(500.0) + std::log(300.0)), 0.0);
  // The representative: predicted back to 60 s with q = 0, the first report's ln det is ln(1e4·9e4)
  // a component, every later one's ln 1e4 (ties keep the earliest): the report at 62 s. Against it,
  // to the midpoint 51 s: e = (−1 800, 1 800, 200, −200), S = diag(20 242, 2) a component:
  // m² = 2·1 800²/20 242 + 2·200²/2 ≈ 40 320, far outside the gate.
  EXPECT_NEAR(gap_statistic(f.tracks, 20, 123, 0.0).m2, 2.0 * 1800.0 * 1800.0 / 20242.0 + 40000.0, 1e-6);
  TrackStitchOptions first = no_manoeuvre();
  first.start_density_bins = false;
  first.gap_bin_s = 0.0;
  first.start_reports = 1;
  // Stitched from the three fragments alone: the summary and the targets.
  auto stitched = [&](const TrackStitchOptions& o) {
    AssociationRecord rec = singletons({{0, 1}, {1, 99}, {1, 7}});
    const TrackStitchSummary summary = stitch_fragments(f, rec, o);
    return std::pair{summary, rec.target};
  };
  const auto [old_rule, before] = stitched(first);
  EXPECT_EQ(old_rule.candidates, 1);
  EXPECT_EQ(old_rule.stitches, 1);
  EXPECT_EQ(before, (std::vector<int32_t>{0, 1, 0}));
  TrackStitchOptions representative = first;
  representative.start_reports = 16;
  const auto [new_rule, after] = stitched(representative);
  EXPECT_EQ(new_rule.candidates, 0);
  EXPECT_EQ(new_rule.stitches, 0);
  EXPECT_EQ(after, (std::vector<int32_t>{0, 1, 2}));
}

// A track whose first reports are a transient (P = diag(1000², 1000², 100², 100²) at 30-38 s),
// then settled (P = diag(100², 100², 1, 1) from 40 s), all on the line x = 200 t, y = 0.
void add_transient_track(TrackFile& f, int32_t sensor, int32_t track) {
  Eigen::Matrix4d P0 = Eigen::Matrix4d::Zero(), P = Eigen::Matrix4d::Zero();
  P0.diagonal() << 1e6, 1e6, 1e4, 1e4;
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  for (double t = 30.0; t <= 100.0 + 1e-9; t += 2.0)
    f.tracks.push_back(sensor, track, t, Eigen::Vector4d(200 * t, 0, 200, 0), t < 40.0 ? P0 : P, -1);
}

TEST(TrackStitching, AnOverlapWithinTheNewTracksTransientIsJoinedWhenNoSensorHoldsTwoTracks) {
  // A (sensor 0) runs along +x at 200 m/s, 0-40 s; B (sensor 1) starts at 30 s on the same line: they
  // overlap by 10 s (> max_overlap_s = 2 s), all of it B's transient. B's representative (predicted
  // back to 30 s with q = 0: ln det 2 ln(1e6·1e4) for the transient reports, 2 ln(1e4) for every
  // settled one, ties keep the earliest) is its report at 40 s, A's last time: e = 0,
  // S = diag(2e4, 2e4, 2, 2), c = ½(4 ln 2π + 2 ln 4e4) ≈ 14.27 against ln V ≈ 34.05 (the box of A's
  // start, B's representative and the background: 68 km · 60 km · 500 · 300 m/s): a join.
  TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, kBackground});  // rows 0-20 A, 21-121 background
  add_transient_track(f, 1, 7);                                   // rows 122-157, 40 s: row 127
  const double c = 0.5 * (kLog2Pi4 + 2.0 * std::log(4e4));
  EXPECT_NEAR(join_cost(f.tracks, 20, 127, no_manoeuvre(), kGate), c, 1e-9);
  EXPECT_LT(c - (std::log(68000.0) + std::log(60000.0) + std::log(500.0) + std::log(300.0)), 0.0);
  TrackStitchOptions o = no_manoeuvre();
  o.start_density_bins = false;
  o.gap_bin_s = 0.0;
  auto stitched = [&](const TrackFile& file, AssociationRecord rec, const TrackStitchOptions& options) {
    const TrackStitchSummary summary = stitch_fragments(file, rec, options);
    return std::pair{summary.stitches, rec.target};
  };
  const AssociationRecord rec = singletons({{0, 1}, {1, 99}, {1, 7}});
  EXPECT_EQ(stitched(f, rec, o), std::pair(1, std::vector<int32_t>{0, 1, 0}));
  TrackStitchOptions within_max_overlap = o;  // the rule before: the 10 s overlap is never a candidate
  within_max_overlap.transient_overlap = false;
  EXPECT_EQ(stitched(f, rec, within_max_overlap), std::pair(0, std::vector<int32_t>{0, 1, 2}));
  // B's group also holds a sensor-0 track over the same 10 s: the join would give the target two
  // simultaneous sensor-0 tracks, so it is refused.
  add_transient_track(f, 0, 5);
  AssociationRecord two = singletons({{0, 1}, {1, 99}, {1, 7}});
  two.tuples[4] = 5;  // the tuple of (1, 7) holds (0, 5) too
  EXPECT_EQ(stitched(f, two, o), std::pair(0, std::vector<int32_t>{0, 1, 2}));
}

TEST(TrackStitching, TheCandidateSearchPreGatesTheStartsRepresentativeNotItsFirstReport) {
  // A runs along +x at 200 m/s (0-40 s); B continues it from 60 s, but B's first report is a poor
  // one: at (12 km, 0) with velocity 0 and P = diag(2e4, 2e4, 1, 1) (the rows after it: on A's line,
  // P = diag(100², 100², 1, 1)). Its ln det is the larger, so B's representative is the report at
  // 62 s. To the midpoint 50 s the first report is 2 km from A's end, beyond √(γ·tr S_pp) =
  // √(23.51·2(1e4 + 100 + 2e4)) ≈ 1.19 km, and the index's reach (h/2)(|v_a| + |v_b|) + √(γ(τ_a + τ_b))
  // ≈ 10·200 + 1.19 km is less than the 4 km between A's end and that report: a search on first
  // reports finds nothing. The representative is on A's line: to the midpoint 51 s, e = 0 and
  // S = diag(20 242, 20 242, 2, 2), a join.
  TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, kBackground});
  Eigen::Matrix4d P0 = Eigen::Matrix4d::Zero(), P = Eigen::Matrix4d::Zero();
  P0.diagonal() << 2e4, 2e4, 1.0, 1.0;
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  f.tracks.push_back(1, 7, 60.0, Eigen::Vector4d(12000, 0, 0, 0), P0, -1);  // row 122
  for (double t = 62.0; t <= 100.0 + 1e-9; t += 2.0)
    f.tracks.push_back(1, 7, t, Eigen::Vector4d(200 * t, 0, 200, 0), P, -1);
  EXPECT_TRUE(gap_surely_outside(f.tracks, 20, 122, 0.0, kGate));
  EXPECT_GT(2000.0 * 2000.0, kGate * 2 * (1e4 + 100 + 2e4));
  EXPECT_NEAR(gap_statistic(f.tracks, 20, 123, 0.0).m2, 0.0, 1e-9);
  EXPECT_NEAR(join_cost(f.tracks, 20, 123, no_manoeuvre(), kGate),
              0.5 * (kLog2Pi4 + 2.0 * std::log(20242.0 * 2.0)), 1e-9);
  AssociationRecord rec = singletons({{0, 1}, {1, 99}, {1, 7}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.candidates, 1);
  EXPECT_EQ(s.stitches, 1);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 0}));
}

TEST(TrackStitching, BadOptionsNameTheField) {
  const std::vector<std::pair<std::function<void(TrackStitchOptions&)>, std::string>> cases{
      {[](TrackStitchOptions& o) { o.max_gap_s = -1; }, "stitching.max_gap_s"},
      {[](TrackStitchOptions& o) { o.turn_probability = 1.5; }, "stitching.turn_probability"},
      {[](TrackStitchOptions& o) { o.turn_sigma = -2; }, "stitching.turn_sigma"},
      {[](TrackStitchOptions& o) { o.turn_prior_joins = -1; }, "stitching.turn_prior_joins"},
      {[](TrackStitchOptions& o) { o.gap_bin_s = -20; }, "stitching.gap_bin_s"},
      {[](TrackStitchOptions& o) { o.start_reports = 0; }, "stitching.start_reports"},
      {[](TrackStitchOptions& o) { o.start_reports = 17; }, "stitching.start_reports"}};
  for (const auto& [spoil, field] : cases) {
    TrackStitchOptions bad;
    spoil(bad);
    try {
      bad.validate();
      FAIL() << field;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace trackassoc
