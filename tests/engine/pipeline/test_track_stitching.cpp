// Fragment stitching by track segment association (engine/pipeline/track_stitching.hpp) on
// hand-made files (tests/support/stitching_files.hpp): the gap statistic, the gate and its pre-gate,
// the assignment of joins, coexisting groups, the start's representative and the transient overlap.
// Every cost is worked out by hand from the closed form of the midpoint prediction, and the joins are
// checked against the assignment that those costs imply. The turn weight: test_stitch_turn_weight.cpp;
// the gap prior and the start density: test_stitch_priors.cpp.
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
