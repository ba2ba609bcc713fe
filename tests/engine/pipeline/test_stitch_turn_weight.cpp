// Fragment stitching's manoeuvring model and its learnt weight (engine/pipeline/track_stitching.hpp,
// kernels/statistics/mixture_weight.hpp) on hand-made files (tests/support/stitching_files.hpp): a
// turn bridged by the mixture, the weight learnt from a file of straight handovers, the weight over
// the gap's span, the quiet σ_a learnt, the revised cost against a fresh one, a near rival, and a
// jump beyond the manoeuvring gate. Costs by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>

#include "engine/pipeline/stitch_join_cost.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "kernels/statistics/chi_square.hpp"
#include "tests/support/stitching_files.hpp"

namespace trackassoc {
namespace {

using namespace stitching_test;

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
  defaults.learn_quiet_sigma = false;   // and its quiet σ_a
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

// 200 handovers, each 40 s on sensor 0, a 60 s gap, 60 s on sensor 1, at random places (±500 km) and
// headings (200 m/s), 400 s apart; B's start is A's end predicted by constant velocity plus w ~ N(0,
// Q(60 s)) per axis, Q of white-noise acceleration σ_a = `sigma` (Bar-Shalom, Li, Kirubarajan 2001
// §6.2.2: [[qτ³/3, qτ²/2], [qτ²/2, qτ]], q = σ_a²); 0: B continues A exactly.
TrackFile handovers_with_acceleration(double sigma, std::vector<std::pair<int32_t, int32_t>>& keys) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> place(-5e5, 5e5), heading(0.0, 2.0 * std::numbers::pi);
  std::normal_distribution<double> n01;
  const double q = sigma * sigma, tau = 60.0;
  Eigen::Matrix2d Q;
  Q << q * tau * tau * tau / 3.0, q * tau * tau / 2.0, q * tau * tau / 2.0, q * tau;
  const Eigen::Matrix2d L = q > 0.0 ? Eigen::Matrix2d(Q.llt().matrixL()) : Eigen::Matrix2d::Zero();
  std::vector<Segment> segments{kBackground};
  keys = {{1, 99}};
  for (int32_t k = 0; k < 200; ++k) {
    const double T = 1000.0 + 400.0 * k, h = heading(rng), px = place(rng), py = place(rng);
    const double vx = 200.0 * std::cos(h), vy = 200.0 * std::sin(h);
    segments.push_back({0, 100 + k, T, T + 40, px - vx * T, vx, py - vy * T, vy});  // at (px, py) at T
    const double tb = T + 100.0;
    const Eigen::Vector2d wx = L * Eigen::Vector2d(n01(rng), n01(rng)),
                          wy = L * Eigen::Vector2d(n01(rng), n01(rng));
    const double bvx = vx + wx(1), bvy = vy + wy(1);
    const double bx = px + vx * 100.0 + wx(0), by = py + vy * 100.0 + wy(0);  // B's position at tb
    segments.push_back({1, 200 + k, tb, tb + 60, bx - bvx * tb, bvx, by - bvy * tb, bvy});
    keys.push_back({0, 100 + k});
    keys.push_back({1, 200 + k});
  }
  return hand_made(segments);
}

TEST(TrackStitching, TheQuietSigmaIsLearntFromTheJoinsAndNotBelowTheFirstAssignments) {
  // An injected σ_a = 8 m/s² (between the grid's 3·2^{6/4} ≈ 7.13 and 3·2^{7/4} ≈ 8.49) is recovered
  // within one step of the grid (|ln(σ̂/8)| < ln 2 / 4) from 200 joins, which outweigh the prior
  // (median 6); exact continuations give the grid's floor, the first assignment's σ_a = 3 (their
  // likelihood is largest at the sharpest model: at e = 0 only ln det S counts); not learning
  // reports 0.
  TrackStitchOptions o;
  o.start_density_bins = false;
  o.gap_bin_s = 0.0;
  std::vector<std::pair<int32_t, int32_t>> keys;
  const TrackFile manoeuvring = handovers_with_acceleration(8.0, keys);
  AssociationRecord rec = singletons(keys);
  const TrackStitchSummary s = stitch_fragments(manoeuvring, rec, o);
  EXPECT_GE(s.stitches, 190);
  EXPECT_LT(std::fabs(std::log(s.quiet_sigma / 8.0)), std::log(2.0) / 4.0) << s.quiet_sigma;
  const TrackFile straight = handovers_with_acceleration(0.0, keys);
  AssociationRecord exact = singletons(keys);
  const TrackStitchSummary e = stitch_fragments(straight, exact, o);
  EXPECT_EQ(e.stitches, 200);
  EXPECT_EQ(e.quiet_sigma, o.manoeuvre_sigma);
  TrackStitchOptions given = o;
  given.learn_quiet_sigma = false;
  AssociationRecord fixed = singletons(keys);
  EXPECT_EQ(stitch_fragments(manoeuvring, fixed, given).quiet_sigma, 0.0);
}

// The second assignment's revised cost (JoinCostRevision) is join_cost at the learnt quiet σ_a
// and turn weight, computed afresh: on the turn above and on a straight continuation 500 m off,
// at σ_a unchanged (the weights alone, from the float ratio), one and two grid steps up, and at
// several weights; the ratio it leaves is join_cost's at the new σ_a.
TEST(TrackStitching, TheRevisedCostIsTheJoinCostAtTheLearntModel) {
  const TrackFile turn =
      hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 100, 160, 14000, 0, 6000 - 200 * 100, 200}, kBackground});
  const TrackFile straight = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 500, 200}, kBackground});
  TrackStitchOptions first;  // the first assignment's model: σ_a = manoeuvre_sigma, π = turn_probability
  first.turn_probability = 0.2;
  for (const TrackFile* f : {&turn, &straight})
    for (const double sigma : {first.manoeuvre_sigma, first.manoeuvre_sigma * std::exp2(0.25),
                               first.manoeuvre_sigma * std::exp2(0.5)})
      for (const double weight : {0.01, 0.2, 0.7}) {
        SCOPED_TRACE(std::string(f == &turn ? "turn" : "straight") + ", sigma_a " + std::to_string(sigma) +
                     ", weight " + std::to_string(weight));
        double d = 0.0;
        const double was = join_cost(f->tracks, 20, 21, first, kGate, &d);
        ASSERT_TRUE(std::isfinite(was));
        float ratio = static_cast<float>(d);
        const double revised = was + JoinCostRevision(first, sigma)(f->tracks, 20, 21, weight, ratio);
        TrackStitchOptions now = first;
        now.manoeuvre_sigma = sigma;
        now.turn_probability = weight;
        double d_now = 0.0;
        const double fresh = join_cost(f->tracks, 20, 21, now, kGate, &d_now);
        // σ_a unchanged: the ratio was kept in float, and the revision moves by at most the ratio's
        // rounding (it is 1-Lipschitz in the ratio); otherwise exact but for round-off.
        const double rounding =
            sigma == first.manoeuvre_sigma ? std::fabs(d - static_cast<double>(static_cast<float>(d))) : 0.0;
        EXPECT_NEAR(revised, fresh, rounding + 1e-12 * (1.0 + std::fabs(fresh)));
        EXPECT_EQ(ratio, static_cast<float>(d_now));
      }
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

}  // namespace
}  // namespace trackassoc
