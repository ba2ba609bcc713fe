// Track segments that overlap (engine/pipeline/track_segments.hpp, rule (a)): segments that overlap
// by more than max_overlap_s (two tracks at once, not one after the other) never join one target on
// one sensor, unless the overlap is the earlier track's coasted tail (its position variance growing
// report by report) and the new one continues it, or the earlier track is lost and the new one
// takes it over (in a join or a merge); only the earlier track's tail is left out; the tail and the
// lost-track tests by hand (engine/pipeline/coasted_tail.hpp).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/coasted_tail.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/io_test_files.hpp"
#include "tests/support/track_segment_files.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;

// Two coasted predictions (36 and 40 s), each 1.25² times the variance before.
TrackFile coasted_file() { return lost_file({{36.0, 1.25 * 1.25}, {40.0, std::pow(1.25, 4)}}); }

TEST(TrackSegments, ASuccessorJoinsBesideTheCoastedTailOfTheTrackItContinues) {
  // The old track and its successor overlap 36-40 s (4 s > max_overlap_s = 2 s): two tracks at
  // once by their report intervals. The old track's last two reports grow in position variance
  // by 1.25² ≈ 1.56 > (1 + coast_growth)² = 1.21 each, a coasted tail: left out, the two follow each
  // other (its last update at 32 s, the successor from 36 s), and the successor continues that
  // update. Without the coast rule (coast_growth 0) the overlap refuses every join.
  const TrackFile f = coasted_file();
  SegmentOptions no_coast;
  no_coast.coast_growth = 0.0;
  const AssociationMetrics mp = nothing_correct_with(f, no_coast);
  const AssociationOutcome seg = segments_make_every_target_correct(f, mp);
  ASSERT_TRUE(seg.summary.segments.has_value());
  EXPECT_EQ(seg.summary.segments->duplicates, 0) << "a successor is no duplicate";
}

// The coasted tail by hand: variances 100, 100, 100, 150, 230 (growth 1.5 and 1.53 > 1.1² = 1.21)
// end in a tail of two reports, the last update the third; reports given out of time order, and
// more reports than the window keeps, find the same; a growth of 0, or of 0.3 (1.53 < 1.3²), finds
// no tail.
TEST(TrackSegments, TheCoastedTailByHand) {
  LatestReports in_order, shuffled, long_track;
  const double variance[5] = {100, 100, 100, 150, 230};
  for (int k = 0; k < 5; ++k) in_order.add(4.0 * k, variance[k], static_cast<std::size_t>(k));
  for (int k : {3, 0, 4, 2, 1}) shuffled.add(4.0 * k, variance[k], static_cast<std::size_t>(k));
  for (int k = -4; k < 5; ++k)
    long_track.add(4.0 * k, k < 0 ? 100.0 : variance[k], static_cast<std::size_t>(k + 4));
  EXPECT_EQ(in_order.t[in_order.held(0.1)], 8.0);
  EXPECT_EQ(in_order.row[in_order.held(0.1)], 2u);
  EXPECT_EQ(shuffled.t[shuffled.held(0.1)], 8.0);
  EXPECT_EQ(long_track.t[long_track.held(0.1)], 8.0);
  EXPECT_EQ(in_order.t[in_order.held(0.0)], 16.0);
  EXPECT_EQ(in_order.t[in_order.held(0.3)], 16.0) << "growth 1.53 < 1.3² = 1.69: no tail";
}

TEST(TrackSegments, OnlyTheEarlierTracksTailIsLeftOut) {
  // Beside every target's track on sensor 1, which goes on updating to the end, a false track
  // (truth −1: started on clutter and a plot) reports the target's state 2.5 σ off in x, once at 36 s
  // or at the track's first report, and then coasts (3 more reports 4 s apart, each 1.25² times the
  // variance before): a track that is all tail after its first report. Leaving *its* tail out as
  // well, the two overlapped by 0 s and the false track joined the target (a false tuple per target,
  // as on widearea: 10 of 25 targets); only the earlier track's tail is left out, so the two overlap
  // by 12 s and the false track stays a tuple of one. Starting on the same scan as the target's
  // track (1 σ off), neither is the earlier one: no tail is left out, and no target holds both
  // (before, 5 did).
  for (const bool same_start : {false, true}) {
    TrackFile f = broken_file(1e9, 1e9);  // the two sensors, unbroken
    const int32_t s1 = f.sensors[1].id;
    std::map<int32_t, std::size_t> start;  // sensor 1's track → the row the false track starts from
    for (std::size_t r = 0; r < f.tracks.size(); ++r) {
      if (f.tracks.sensor[r] != s1) continue;
      auto [it, fresh] = start.try_emplace(f.tracks.track[r], r);
      const double t = f.tracks.t[r], t_kept = f.tracks.t[it->second];
      if (same_start ? t < t_kept : (t == 36.0 && t_kept != 36.0)) it->second = r;
    }
    for (const auto& [track, r] : start) {
      if (!same_start && f.tracks.t[r] != 36.0) continue;
      double factor = 1.0;
      for (int k = 0; k < 4; ++k) {
        auto x = f.tracks.state_at(r);
        const auto P = f.tracks.cov_at(r);
        x[0] += x[2] * 4.0 * k + (same_start ? 1.0 : 2.5) * std::sqrt(P(0, 0)), x[1] += x[3] * 4.0 * k;
        f.tracks.push_back(s1, track + kRenumber, f.tracks.t[r] + 4.0 * k, x, P * factor, -1);
        factor *= 1.25 * 1.25;
      }
    }
    const AssociationRecord rec = associate(f, true).record;
    // Rule (a) itself: no target holds a track of sensor 1 and its false companion.
    std::map<int32_t, std::set<int32_t>> of_target;  // target → its tracks on sensor 1
    for (std::size_t k = 0; k < rec.num_tuples(); ++k)
      if (rec.tuples[2 * k + 1] >= 0) of_target[rec.target[k]].insert(rec.tuples[2 * k + 1]);
    int32_t both = 0;
    for (const auto& [target, tracks] : of_target)
      for (int32_t t : tracks) both += t < kRenumber && tracks.count(t + kRenumber);
    EXPECT_EQ(both, 0) << (same_start ? "on the target's first scan" : "at 36 s");
    if (same_start) continue;  // 1 σ off from the start, some false tracks win the assignment itself
    const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, rec);
    ASSERT_GT(m.targets, 3);
    EXPECT_EQ(m.correct, m.targets);
    EXPECT_EQ(m.false_tuples, 0);
  }
}

TEST(TrackSegments, ASuccessorTakesOverFromALostTrack) {
  // The old track goes on reporting 12 s into its successor (36-48 s), updated now and then: its
  // variance grows at 36, 40 and 48 s (by 1.25² > (1 + coast_growth)² = 1.21) and falls at 44 s, so
  // no unbroken tail ends it (its last report before the tail is at 44 s, 8 s into the successor).
  // After the successor's first report 2 of its 3 reports grow: a lost track, whose successor
  // continues its report at 36 s. Without the takeover (takeover_s 0) the overlap refuses every join.
  const double g = 1.25 * 1.25;
  const TrackFile f = lost_file({{36.0, g}, {40.0, g * g}, {44.0, g}, {48.0, g * g}});
  SegmentOptions no_takeover;
  no_takeover.takeover_s = 0.0;
  segments_make_every_target_correct(f, nothing_correct_with(f, no_takeover));
}

TEST(TrackSegments, OnlyALostTrackIsTakenOver) {
  // The same kind of overlap, the old track not lost (its variance factors against 32 s after 36 s,
  // where the successor starts): level at every report (a second craft tracked beside the target,
  // as far as its covariance tells); one growth (44 s) of two; two growths (40, 56 s) of five, fewer
  // than half; two growths of three (40, 44 s) but a fall at the end (48 s: not coasting). Neither
  // follows the other (no unbroken tail either), so each target's two tracks stay split.
  const double g = 1.25 * 1.25;
  for (const std::map<double, double>& after :
       {std::map<double, double>{{36.0, 1.0}, {40.0, 1.0}, {44.0, 1.0}, {48.0, 1.0}},
        std::map<double, double>{{36.0, g}, {40.0, g}, {44.0, g * g}},
        std::map<double, double>{
            {36.0, g}, {40.0, g * g}, {44.0, g * g}, {48.0, g * g}, {52.0, g * g}, {56.0, g * g * g}},
        std::map<double, double>{{36.0, g}, {40.0, g * g}, {44.0, g * g * g}, {48.0, g * g}}}) {
    const TrackFile f = lost_file(after);
    const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, associate(f, true).record);
    ASSERT_GT(m.targets, 3);
    EXPECT_EQ(m.correct, 0) << after.size() << " reports after 32 s, the last at " << after.rbegin()->first
                            << " s";
    EXPECT_EQ(m.false_tuples, 0);
  }
}

// lost_file(after) whose sensor 0 breaks too: its tracks end with the report at 32 s and go on from
// 36 s under a new number (number + kRenumber), as sensor 1's successors do. Sensor 1's lost tracks
// report the successor's state (a plot in their gate now and then; a target that turns at 32-36 s
// would leave a constant-velocity prediction, and with it the only link of the early and late
// tuples, outside the gate), with their growing covariances.
TrackFile both_lost_file(const std::map<double, double>& after) {
  TrackFile f = lost_file(after);
  std::map<std::pair<int32_t, double>, std::size_t> successor;  // (lost track, t) → successor's row
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    if (f.tracks.sensor[r] == f.sensors[1].id && f.tracks.track[r] >= kRenumber)
      successor[{f.tracks.track[r] - kRenumber, f.tracks.t[r]}] = r;
  TrackTable out(f.tracks.layout);
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r], track = f.tracks.track[r];
    const double t = f.tracks.t[r];
    const bool lost = s == f.sensors[1].id && track < kRenumber && t > 32.0;
    const auto x = lost ? f.tracks.state_at(successor.at({track, t})) : f.tracks.state_at(r);
    out.push_back(s, s == f.sensors[0].id && t >= 36.0 ? track + kRenumber : track, t, x, f.tracks.cov_at(r),
                  f.tracks.truth[r]);
  }
  f.tracks = out;
  return f;
}

TEST(TrackSegments, ATargetWhoseTrackWasLostMergesWithItsSuccessors) {
  // Both sensors lose every target after 32 s: sensor 0's track ends there, sensor 1's goes on as a
  // lost track to 48 s (growing at every report, as in ASuccessorTakesOverFromALostTrack) while the
  // successors of both report from 36 s. The assignment gives each target an early tuple {A1, B1}
  // and a late one {A2, B2}, no track free to join. The merge allows a takeover (B1 by B2, 12 s of
  // overlap) as a join does; without the takeover (takeover_s 0) B1 and B2 overlap and the targets
  // stay split.
  const double g = 1.25 * 1.25;
  const TrackFile f = both_lost_file({{36.0, g}, {40.0, g * g}, {44.0, g * g * g}, {48.0, g * g * g * g}});
  SegmentOptions no_takeover;
  no_takeover.takeover_s = 0.0;
  const AssociationOutcome seg = segments_make_every_target_correct(f, nothing_correct_with(f, no_takeover));
  ASSERT_TRUE(seg.summary.segments.has_value());
  EXPECT_GT(seg.summary.segments->targets_merged, 0) << "the early and late tuples of a target merge";
}

// The lost-track test by hand: variances 100 (at 0 s), then 150, 100, 160, 250 at 4-16 s. After
// 2 s: growths at 4, 12 and 16 s (1.5, 1.6, 1.56 > 1.21), a fall at 8 s: 3 of 4, lost. After 6 s:
// 12 and 16 of 8-16 s, 2 of 3, lost. After 14 s: one report, one growth (< 2): not lost. After 20 s:
// none. Before every kept report (−1 s): nothing to compare the first with, not lost. A growth of
// 0.3 (1.3² = 1.69 above every step): not lost. Then 100, 150, 150, 150, 150, 150, 240: after 2 s
// two growths of six, fewer than half; 100, 150, 240, 200: two of three, but the last falls; and a
// track of 14 reports, of which the window keeps the latest 12 (from 8 s): after 6 s its first kept
// report has no report before it, so the test refuses.
TEST(TrackSegments, TheLostTrackByHand) {
  LatestReports r;
  const double variance[5] = {100, 150, 100, 160, 250};
  for (int k = 0; k < 5; ++k) r.add(4.0 * k, variance[k], static_cast<std::size_t>(k));
  EXPECT_TRUE(r.lost_after(2.0, 0.1));
  EXPECT_TRUE(r.lost_after(6.0, 0.1));
  EXPECT_FALSE(r.lost_after(14.0, 0.1));
  EXPECT_FALSE(r.lost_after(20.0, 0.1));
  EXPECT_FALSE(r.lost_after(-1.0, 0.1));
  EXPECT_FALSE(r.lost_after(2.0, 0.3));
  EXPECT_EQ(r.last_at_or_before(9.0), 2);
  EXPECT_EQ(r.last_at_or_before(-1.0), -1);
  auto track = [](std::vector<double> v) {
    LatestReports x;
    for (std::size_t k = 0; k < v.size(); ++k) x.add(4.0 * static_cast<double>(k), v[k], k);
    return x;
  };
  EXPECT_FALSE(track({100, 150, 150, 150, 150, 150, 240}).lost_after(2.0, 0.1)) << "2 of 6";
  EXPECT_TRUE(track({100, 150, 150, 240}).lost_after(2.0, 0.1)) << "2 of 3";
  EXPECT_FALSE(track({100, 150, 240, 200}).lost_after(2.0, 0.1)) << "ends with a fall";
  std::vector<double> long_track(14, 100.0);
  for (std::size_t k = 1; k < long_track.size(); ++k) long_track[k] = long_track[k - 1] * (k % 2 ? 1.5 : 1.0);
  long_track.back() = long_track[12] * 1.5;
  const LatestReports full = track(long_track);
  EXPECT_EQ(full.t[0], 8.0);
  EXPECT_TRUE(full.lost_after(10.0, 0.1));
  EXPECT_FALSE(full.lost_after(6.0, 0.1)) << "the report before the first kept one is gone";
}

TEST(TrackSegments, OverlappingTracksDoNotJoin) {
  // The new track starts 20 s before the old one ends: two tracks of one target at once. The rule
  // is checked without the takeover; with it (below) an old track whose missed updates make it look
  // lost may be taken over, which on this file can join only a target's own tracks.
  const TrackFile f = broken_file(60.0, 40.0);
  SegmentOptions no_takeover;
  no_takeover.takeover_s = 0.0;
  const AssociationRecord rec = associate(f, true, 2.0, {}, no_takeover).record;
  const auto span = spans(f);
  std::map<int32_t, std::vector<int32_t>> broken_of_target;  // target → its tracks on sensor 1
  for (std::size_t k = 0; k < rec.num_tuples(); ++k)
    if (rec.tuples[2 * k + 1] >= 0) broken_of_target[rec.target[k]].push_back(rec.tuples[2 * k + 1]);
  for (auto& [t, tracks] : broken_of_target) {
    std::sort(tracks.begin(), tracks.end());
    tracks.erase(std::unique(tracks.begin(), tracks.end()), tracks.end());
    for (std::size_t i = 0; i < tracks.size(); ++i)
      for (std::size_t j = i + 1; j < tracks.size(); ++j) {
        const auto& a = span.at({f.sensors[1].id, tracks[i]});
        const auto& b = span.at({f.sensors[1].id, tracks[j]});
        EXPECT_LE(std::min(a.second, b.second) - std::max(a.first, b.first), 2.0);
      }
  }
  // The takeover joins only an old track that looks lost, here always one target's: no false tuple,
  // nothing correct lost.
  const AssociationMetrics strict = evaluate_association(f.tracks, f.sensors, rec);
  const AssociationMetrics taken = evaluate_association(f.tracks, f.sensors, associate(f, true, 2.0).record);
  EXPECT_EQ(taken.false_tuples, 0);
  EXPECT_GE(taken.correct, strict.correct);
  // With a tolerance above the overlap the same segments do join.
  const AssociationRecord loose = associate(f, true, 25.0).record;
  EXPECT_EQ(evaluate_association(f.tracks, f.sensors, loose).correct,
            evaluate_association(f.tracks, f.sensors, loose).targets);
}

}  // namespace
}  // namespace trackassoc
