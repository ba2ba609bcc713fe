// Track segments joined to their targets (engine/pipeline/track_segments.hpp), against the
// simulator's truth: a simulated two-sensor recording in which one sensor breaks every track in
// two (the old track ends, the new one starts a few seconds later under a new number). The truth
// says which segments are one target; the checks are that
//  * without the segment pass the one-to-one assignment cannot get a broken target right (missed),
//  * with it every target is correct (evaluate_association over target numbers), each tuple's
//    members report at the same times, and every track is in exactly one target;
//  * when both sensors break at different times, a target's early and late tuples merge;
//  * segments that overlap by more than max_overlap_s (two tracks at once, not one after the
//    other) never join one target on one sensor, unless the overlap is the old track's coasted tail
//    (its position variance growing report by report) and the new one continues it;
//  * a duplicate (a second track of one target on one sensor at the same time) joins its target
//    only on a sensor listed in duplicate_sensors, and the duplicate statistic is the hand-worked
//    one;
//  * a doubtful pair (the family-wise veto) neither forbids a join nor is its evidence, and adds its
//    link cost, as in a tuple; a coexisting pair outside both gates forbids it;
//  * the reader refuses bad target numbers, naming the dataset.
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

namespace trackassoc {
namespace {

constexpr int32_t kRenumber = 1000;  // the second segment of track k is track k + kRenumber

// recorded_sync with its first two sensors; sensor c (0, 1) loses every track between t_end[c] and
// t_start[c] (a gap, or an overlap when t_start < t_end), the rows from t_start[c] on taking a new
// number (never: both 1e9).
TrackFile staggered_file(std::array<double, 2> t_end, std::array<double, 2> t_start) {
  const Scenario sc = load_scenario("recorded_sync");
  TrackFile f = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const std::array<int32_t, 2> ids{f.sensors[0].id, f.sensors[1].id};
  f.sensors.resize(2);
  TrackTable out(f.tracks.layout);
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r];
    const int c = s == ids[0] ? 0 : (s == ids[1] ? 1 : -1);
    if (c < 0) continue;
    const double t = f.tracks.t[r];
    const auto x = f.tracks.state_at(r);
    const auto P = f.tracks.cov_at(r);
    if (t < t_end[c]) out.push_back(s, f.tracks.track[r], t, x, P, f.tracks.truth[r]);
    if (t >= t_start[c]) out.push_back(s, f.tracks.track[r] + kRenumber, t, x, P, f.tracks.truth[r]);
  }
  f.tracks = out;
  f.measurements.reset();   // of the dropped sensor too
  f.scenario_json.clear();  // a recorded track set now
  return f;
}

// Sensor 1 broken between t_end and t_start, sensor 0 whole.
TrackFile broken_file(double t_end, double t_start) { return staggered_file({1e9, t_end}, {1e9, t_start}); }

// recorded_sync with its first two sensors; from t_start on, sensor 1 holds a second track of
// every target (number + kRenumber) beside the first, its position shifted by dx along x.
TrackFile duplicate_file(double t_start, double dx) {
  TrackFile f = broken_file(1e9, 1e9);  // the two sensors, unbroken
  const int32_t dup = f.sensors[1].id;
  const std::size_t n = f.tracks.size();
  for (std::size_t r = 0; r < n; ++r) {
    if (f.tracks.sensor[r] != dup || f.tracks.t[r] < t_start) continue;
    auto x = f.tracks.state_at(r);
    x[0] += dx;
    f.tracks.push_back(dup, f.tracks.track[r] + kRenumber, f.tracks.t[r], x, f.tracks.cov_at(r),
                       f.tracks.truth[r]);
  }
  return f;
}

AssociationOutcome associate(const TrackFile& f, bool segments, double max_overlap = 2.0,
                             std::vector<int32_t> duplicate_sensors = {}, SegmentOptions so = {}) {
  AssociatorOptions o;
  o.segments = so;
  o.segments.enabled = segments;
  o.segments.max_overlap_s = max_overlap;
  o.segments.duplicate_sensors = std::move(duplicate_sensors);
  return make_associator(o)->associate(f);
}

std::map<std::pair<int32_t, int32_t>, std::pair<double, double>> spans(const TrackFile& f) {
  std::map<std::pair<int32_t, int32_t>, std::pair<double, double>> out;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    auto [it, fresh] = out.emplace(std::make_pair(f.tracks.sensor[r], f.tracks.track[r]),
                                   std::make_pair(f.tracks.t[r], f.tracks.t[r]));
    it->second.first = std::min(it->second.first, f.tracks.t[r]);
    it->second.second = std::max(it->second.second, f.tracks.t[r]);
  }
  return out;
}

TEST(TrackSegments, BrokenTracksJoinTheirTargets) {
  const TrackFile f = broken_file(40.0, 43.0);
  const AssociationOutcome plain = associate(f, false);
  const AssociationMetrics mp = evaluate_association(f.tracks, f.sensors, plain.record);
  ASSERT_GT(mp.targets, 3);
  EXPECT_EQ(mp.correct, 0) << "a target of three tracks cannot be one tuple of two sensors";
  EXPECT_TRUE(plain.record.target.empty());

  const AssociationOutcome seg = associate(f, true);
  const AssociationRecord& rec = seg.record;
  ASSERT_EQ(rec.target.size(), rec.num_tuples());
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, rec);
  EXPECT_EQ(m.targets, mp.targets);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  // Every track in one target; the members of a tuple of two report at common times.
  const auto span = spans(f);
  std::map<std::pair<int32_t, int32_t>, int32_t> target_of;
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    const int32_t a = rec.tuples[2 * k], b = rec.tuples[2 * k + 1];
    for (int c = 0; c < 2; ++c) {
      const int32_t trk = rec.tuples[2 * k + c];
      if (trk < 0) continue;
      auto [it, fresh] = target_of.emplace(std::make_pair(f.sensors[c].id, trk), rec.target[k]);
      EXPECT_EQ(it->second, rec.target[k]) << "track " << trk << " in two targets";
    }
    if (a >= 0 && b >= 0) {
      const auto& sa = span.at({f.sensors[0].id, a});
      const auto& sb = span.at({f.sensors[1].id, b});
      EXPECT_GT(std::min(sa.second, sb.second) - std::max(sa.first, sb.first), 0.0);
    }
  }
  EXPECT_EQ(target_of.size(), span.size());
  for (const UnassociatedTracks& u : seg.unassociated) EXPECT_TRUE(u.tracks.empty()) << u.sensor_id;
  // Written and read back with the target numbers.
  test::TempDir dir;
  TrackFile out = f;
  store_outcome(out, seg);
  write_track_file(dir.file("seg.h5"), out);
  const TrackFile back = read_track_file(dir.file("seg.h5"));
  ASSERT_EQ(back.associations.size(), 1u);
  EXPECT_EQ(back.associations[0].target, rec.target);
  EXPECT_EQ(back.associations[0].tuples, rec.tuples);
}

// The segment pass on f: every target of the plain assignment's metrics mp correct, no false
// tuple, and the pass's summary present.
AssociationOutcome segments_make_every_target_correct(const TrackFile& f, const AssociationMetrics& mp) {
  AssociationOutcome seg = associate(f, true);
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, seg.record);
  EXPECT_EQ(m.targets, mp.targets);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  EXPECT_TRUE(seg.summary.segments.has_value());
  return seg;
}

TEST(TrackSegments, StaggeredBreaksMergeTheirTargets) {
  // Both sensors break every track, at different times (a radar handing over, a fade on one of
  // them): sensor 0 after its report at 12 s (the new track from 16 s), sensor 1 after 44 s (from
  // 48 s). The one-per-sensor assignment gives each target two tuples, early {A1, B1} and late
  // {A2, B2}; A1 and B2 never report together, so only B1 and A2 (16-44 s) link the two. The merge takes
  // the targets whose members follow each other on each sensor (a), continue by constant velocity
  // (d), are linked over common reports by at least one pair (b) and fail no tested pair (c).
  const TrackFile f = staggered_file({14.0, 46.0}, {15.0, 47.0});
  const AssociationOutcome plain = associate(f, false);
  const AssociationMetrics mp = evaluate_association(f.tracks, f.sensors, plain.record);
  ASSERT_GT(mp.targets, 3);
  EXPECT_EQ(mp.correct, 0) << "a target of four tracks cannot be one tuple of two sensors";

  const AssociationOutcome seg = segments_make_every_target_correct(f, mp);
  ASSERT_TRUE(seg.summary.segments.has_value());
  EXPECT_GT(seg.summary.segments->targets_merged, 0) << "the early and late tuples of a target merge";
  for (const UnassociatedTracks& u : seg.unassociated) EXPECT_TRUE(u.tracks.empty()) << u.sensor_id;
}

// recorded_sync's first two sensors (scans every 4 s from 0 s); sensor 1's tracker loses every
// target after its report at 32 s: the old track goes on reporting at the times of `after` (its
// state at 32 s moved by constant velocity, every covariance entry the given factor times the
// report at 32 s's), while the successor (number + kRenumber) reports the target from 36 s on.
TrackFile lost_file(const std::map<double, double>& after) {
  TrackFile f = broken_file(1e9, 1e9);  // the two sensors, unbroken
  const int32_t lost = f.sensors[1].id;
  TrackTable out(f.tracks.layout);
  std::map<int32_t, std::size_t> last_update;  // sensor 1's track → its row at 32 s
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    if (f.tracks.sensor[r] == lost && f.tracks.t[r] == 32.0) last_update[f.tracks.track[r]] = r;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r], track = f.tracks.track[r];
    const double t = f.tracks.t[r];
    if (s != lost || t <= 32.0)
      out.push_back(s, track, t, f.tracks.state_at(r), f.tracks.cov_at(r), f.tracks.truth[r]);
    if (s != lost) continue;
    if (t >= 36.0)
      out.push_back(s, track + kRenumber, t, f.tracks.state_at(r), f.tracks.cov_at(r), f.tracks.truth[r]);
    if (after.count(t) && last_update.count(track)) {
      const std::size_t u = last_update.at(track);
      auto x = f.tracks.state_at(u);
      const double dt = t - 32.0;
      x[0] += x[2] * dt, x[1] += x[3] * dt;
      out.push_back(s, track, t, x, f.tracks.cov_at(u) * after.at(t), f.tracks.truth[r]);
    }
  }
  f.tracks = out;
  return f;
}

// Two coasted predictions (36 and 40 s), each 1.25² times the variance before.
TrackFile coasted_file() { return lost_file({{36.0, 1.25 * 1.25}, {40.0, std::pow(1.25, 4)}}); }

// The segment pass with options `so` on a file where it makes no target correct (the overlaps
// refused): its metrics, for segments_make_every_target_correct.
AssociationMetrics nothing_correct_with(const TrackFile& f, const SegmentOptions& so) {
  const AssociationMetrics m =
      evaluate_association(f.tracks, f.sensors, associate(f, true, 2.0, {}, so).record);
  EXPECT_GT(m.targets, 3);
  EXPECT_EQ(m.correct, 0)
      << "a successor overlapping its predecessor by > 2 s joins nothing without the rule";
  return m;
}

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

// Rule (d) of a merge by hand: nodes 0, 1, 2 of one sensor report over 0-20, 24-40 and 44-60 s (A1,
// A2, A3). A target holding A1 and A2 merging with one holding A3: only A2 continues to A3 (A1 is not
// A3's predecessor; the rule before asked every pair). A1 and A3 against A2: both steps. Node 3
// (24-30 s) ties with A2 in first report, taken by node. Nested: node 4 (0-100 s) and its duplicate
// node 5 (10-30 s) in one target, node 6 (101-160 s) in the other: 6's predecessor is 4, which
// reports last, not 5.
TEST(TrackSegments, AMergeContinuesEachMembersPredecessor) {
  const std::vector<double> first = {0.0, 24.0, 44.0, 24.0, 0.0, 10.0, 101.0};
  const std::vector<double> last = {20.0, 40.0, 60.0, 30.0, 100.0, 30.0, 160.0};
  using Steps = std::vector<std::pair<int32_t, int32_t>>;
  using Nodes = std::vector<int32_t>;
  EXPECT_EQ(predecessors_across(Nodes{0, 1}, Nodes{2}, first, last), (Steps{{1, 2}}));
  EXPECT_EQ(predecessors_across(Nodes{2}, Nodes{1, 0}, first, last), (Steps{{1, 2}}));
  EXPECT_EQ(predecessors_across(Nodes{0, 2}, Nodes{1}, first, last), (Steps{{0, 1}, {1, 2}}));
  EXPECT_EQ(predecessors_across(Nodes{3}, Nodes{1}, first, last), (Steps{{1, 3}}));
  EXPECT_EQ(predecessors_across(Nodes{4, 5}, Nodes{6}, first, last), (Steps{{4, 6}}));
  EXPECT_EQ(predecessors_across(Nodes{4}, Nodes{5, 6}, first, last), (Steps{{4, 5}, {4, 6}}));
  EXPECT_TRUE(predecessors_across(Nodes{0, 1}, Nodes{}, first, last).empty());
}

TEST(TrackSegments, ATargetThatTurnedMergesThroughTheTrackThatFollowedTheTurn) {
  // Every target turns by 45° at 28 s (the reports after 28 s rotated about the mean of the target's
  // reports at 28 s, by truth; states and covariances). Sensor 0 breaks its tracks twice: A1 to 20 s, A2
  // 24-40 s, A3 from 44 s; sensor 1 once: B1 to 32 s, B2 from 36 s. No extrapolation (max_extrapolation 0),
  // so only tracks that report together are compared. The target's tuples {A1, B1} and {A3, B2} (A2 joins one
  // of them) merge when each member's predecessor on the other target continues to it: A2 to A3 (or A1 to A2)
  // and B1 to B2, all after the turn or all before it. A1's last report (20 s, before the turn) does not
  // predict A3 (44 s, after it): asked of every pair, as the rule was, 8 of the 25 targets stayed split.
  TrackFile f = broken_file(1e9, 1e9);  // the two sensors, unbroken
  const int32_t s0 = f.sensors[0].id;
  std::map<int32_t, std::pair<Eigen::Vector2d, int>> at_turn;  // truth → Σ of its positions at 28 s, count
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    if (f.tracks.t[r] == 28.0) {
      auto& [sum, n] = at_turn.try_emplace(f.tracks.truth[r], Eigen::Vector2d::Zero(), 0).first->second;
      sum += f.tracks.state_at(r).head(2);
      ++n;
    }
  const double c45 = std::sqrt(0.5);  // 45° to the left, on position and velocity
  Eigen::Matrix4d R = Eigen::Matrix4d::Zero();
  R(0, 0) = R(1, 1) = R(2, 2) = R(3, 3) = c45;
  R(0, 1) = R(2, 3) = -c45;
  R(1, 0) = R(3, 2) = c45;
  TrackTable out(f.tracks.layout);
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r];
    const double t = f.tracks.t[r];
    Eigen::VectorXd x = f.tracks.state_at(r);
    Eigen::MatrixXd P = f.tracks.cov_at(r);
    const auto turn = at_turn.find(f.tracks.truth[r]);
    if (t > 28.0 && turn != at_turn.end()) {
      const Eigen::Vector2d c = turn->second.first / turn->second.second;
      x.head(2) -= c;  // velocities rotate about zero, positions about c
      x = R * x;
      x.head(2) += c;
      P = R * P * R.transpose();
    }
    int32_t track = f.tracks.track[r];
    if (s == s0) {
      if ((t > 20.0 && t < 24.0) || (t > 40.0 && t < 44.0)) continue;
      track += t >= 44.0 ? 2 * kRenumber : (t >= 24.0 ? kRenumber : 0);
    } else {
      if (t > 32.0 && t < 36.0) continue;
      track += t >= 36.0 ? kRenumber : 0;
    }
    out.push_back(s, track, t, x, P, f.tracks.truth[r]);
  }
  f.tracks = out;
  AssociatorOptions o;
  o.pipeline.alignment.max_extrapolation = 0.0;
  o.segments.enabled = false;
  const AssociationMetrics mp =
      evaluate_association(f.tracks, f.sensors, make_associator(o)->associate(f).record);
  ASSERT_GT(mp.targets, 3);
  EXPECT_LE(mp.correct, 1) << "a target of five tracks cannot be one tuple of two sensors";
  o.segments.enabled = true;
  const AssociationOutcome seg = make_associator(o)->associate(f);
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, seg.record);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  ASSERT_TRUE(seg.summary.segments.has_value());
  EXPECT_GT(seg.summary.segments->targets_merged, 0);
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

TEST(TrackSegments, DuplicateStatisticByHand) {
  // Two tracks, D = 4, 4 common times. Position blocks differ per track and time, with an
  // off-diagonal term; the velocity blocks are I for both, so C_vel = 2I. A 2 × 2 position block
  // C = [[a, b], [b, d]] gives Δᵀ C⁻¹ Δ = (d Δx² − 2b Δx Δy + a Δy²) / (ad − b²).
  AlignedTracks a;
  a.dim = 4;
  a.n_times = 4;
  a.times = {0.0, 1.0, 2.0, 3.0};
  a.track = {0, 1};
  a.truth = {-1, -1};
  a.state.assign(2 * 4 * 4, 0.0);
  a.cov.assign(2 * 4 * 10, 0.0);
  a.valid = {1, 1, 1, 1, 1, 1, 0, 1};
  a.span_begin = {0, 0};  // both over the 4 common times
  a.span_offset = {0, 4, 8};
  // packed upper triangle: (0,0) (0,1) (0,2) (0,3) (1,1) (1,2) (1,3) (2,2) (2,3) (3,3)
  auto cov = [&](int track, int k, double xx, double xy, double yy) {
    double* P = &a.cov[(track * 4 + k) * 10];
    P[0] = xx, P[1] = xy, P[4] = yy, P[7] = P[9] = 1.0;
  };
  cov(0, 0, 4, 1, 2), cov(1, 0, 2, 1, 6);   // C = [[6, 2], [2, 8]], det 44
  cov(0, 1, 1, 0, 1), cov(1, 1, 3, 0, 3);   // C = 4 I
  cov(0, 3, 1, 0, 1), cov(1, 3, -3, 0, 1);  // C = [[-2, 0], [0, 2]]: not positive definite
  auto set = [&](int track, int k, std::array<double, 4> x) {
    std::copy(x.begin(), x.end(), a.state.begin() + (track * 4 + k) * 4);
  };
  set(1, 0, {4, 2, 0, 0});   // (8·16 − 2·2·4·2 + 6·4) / 44 = 120 / 44
  set(1, 1, {0, 4, 1, 0});   // 16/4 + 1/2 = 4.5
  set(1, 2, {40, 0, 0, 0});  // track 1 not valid at k = 2: skipped
  const DuplicateStatistic d = duplicate_statistic(a, 0, 1, 0.0, 2.5);
  EXPECT_EQ(d.times, 2);
  EXPECT_NEAR(d.max_d2, 4.5, 1e-12);
  EXPECT_NEAR(duplicate_statistic(a, 0, 1, 0.0, 0.5).max_d2, 120.0 / 44.0, 1e-12);
  EXPECT_NEAR(duplicate_statistic(a, 1, 0, 0.0, 0.5).max_d2, 120.0 / 44.0, 1e-12);  // symmetric
  const DuplicateStatistic all = duplicate_statistic(a, 0, 1, 0.0, 3.0);
  EXPECT_EQ(all.times, 3);
  EXPECT_EQ(all.max_d2, std::numeric_limits<double>::infinity());
}

TEST(TrackSegments, DuplicatesJoinOnlyOnTheirSensor) {
  const TrackFile f = duplicate_file(40.0, 3.0);
  const int32_t dup = f.sensors[1].id;
  // Target number of every sensor-1 track.
  auto targets = [&](const AssociationRecord& rec) {
    std::map<int32_t, int32_t> out;
    for (std::size_t k = 0; k < rec.num_tuples(); ++k)
      if (rec.tuples[2 * k + 1] >= 0) out[rec.tuples[2 * k + 1]] = rec.target[k];
    return out;
  };
  const auto span = spans(f);
  int32_t duplicates = 0;
  for (const auto& [key, s] : span) duplicates += key.first == dup && key.second >= kRenumber;
  ASSERT_GT(duplicates, 3);

  const auto plain = targets(associate(f, true).record);  // sensor 1 not listed: no duplicate joins
  const auto joined = targets(associate(f, true, 2.0, {dup}).record);
  int32_t together_plain = 0, together = 0;
  for (const auto& [key, s] : span) {
    if (key.first != dup || key.second < kRenumber) continue;
    const int32_t first = key.second - kRenumber;
    together_plain += plain.at(first) == plain.at(key.second);
    together += joined.at(first) == joined.at(key.second);
  }
  EXPECT_EQ(together_plain, 0);
  EXPECT_EQ(together, duplicates);
  // The duplicate gate binds: with a probability so small that χ²₄ is below the twins' statistic,
  // or more common times than they have, no twin joins.
  auto together_with = [&](const SegmentOptions& so) {
    const auto m = targets(associate(f, true, 2.0, {dup}, so).record);
    int32_t n = 0;
    for (const auto& [key, s] : span)
      if (key.first == dup && key.second >= kRenumber) n += m.at(key.second - kRenumber) == m.at(key.second);
    return n;
  };
  SegmentOptions tight;
  tight.duplicate_probability = 1e-12;
  EXPECT_EQ(together_with(tight), 0);
  SegmentOptions long_overlap;
  long_overlap.min_duplicate_times = 100000;
  EXPECT_EQ(together_with(long_overlap), 0);
  // Every target right when the duplicates count as its tracks.
  const AssociationRecord rec = associate(f, true, 2.0, {dup}).record;
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, rec);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  // A sensor that is not associated is refused, by name.
  try {
    associate(f, true, 2.0, {12345});
    FAIL() << "an unknown duplicate sensor was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate_sensors"), std::string::npos) << e.what();
  }
}

// recorded_sync's first three sensors; the third breaks every track after its report at 40 s (the
// new track, number + kRenumber, from 43 s).
TrackFile third_sensor_broken() {
  const Scenario sc = load_scenario("recorded_sync");
  TrackFile f = simulation_to_track_file(sc, simulate(sc, 1, 0));
  f.sensors.resize(3);
  const int32_t broken = f.sensors[2].id;
  TrackTable out(f.tracks.layout);
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r];
    if (s != f.sensors[0].id && s != f.sensors[1].id && s != broken) continue;
    const double t = f.tracks.t[r];
    const int32_t track = f.tracks.track[r] + (s == broken && t >= 43.0 ? kRenumber : 0);
    if (s == broken && t > 41.0 && t < 43.0) continue;
    out.push_back(s, track, t, f.tracks.state_at(r), f.tracks.cov_at(r), f.tracks.truth[r]);
  }
  f.tracks = out;
  f.measurements.reset();
  f.scenario_json.clear();
  return f;
}

TEST(TrackSegments, ADoubtfulPairNeitherForbidsAJoinNorLinksIt) {
  // The assignment puts one segment of each broken track into its target's triple; the pass joins
  // the other (the free segment) through its gated pairs with sensors 0 and 1. Here the free
  // segments' pairs with sensor 1 become doubtful at link cost +0.5 (outside the gate, inside the
  // family-wise gate): the joins stay, each joined tuple holding such a pair costs 0.5 − c more (c
  // the pair's gated link cost), as a tuple counts it (engine/pipeline/tuple_cost.hpp). Made
  // coexisting pairs outside both gates instead, they forbid the joins (rule (c)).
  const TrackFile f = third_sensor_broken();
  const SparseSDOptions o;  // the default path's
  const SparseSDProblem p = build_sparse_sd_problem(f, o);
  ASSERT_EQ(p.S(), 3);
  const AssociationRecord rec = solve_sparse_sd_association(p, "lr+ls", nlohmann::json::object(), 1, o);
  std::set<int32_t> assigned;  // sensor 2's tracks in the assignment's tuples of two or more
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    int32_t members = 0;
    for (int c = 0; c < 3; ++c) members += rec.tuples[3 * k + c] >= 0;
    if (members >= 2 && rec.tuples[3 * k + 2] >= 0) assigned.insert(rec.tuples[3 * k + 2]);
  }
  const std::size_t slot = 1 * 3 + 2;
  std::map<std::pair<int32_t, int32_t>, double> moved;  // (track on 1, free track on 2) → gated link cost
  auto with_free_pairs = [&](bool doubtful) {
    SparseSDProblem q = p;
    SparsePairStatistic kept = q.pairs[slot];
    kept.a.clear(), kept.b.clear(), kept.lambda.clear(), kept.dof.clear(), kept.in_gate.clear();
    std::vector<double> kept_link;
    q.doubtful.resize(9);
    q.doubtful_link.resize(9);
    q.doubtful[slot] = SparsePairStatistic{};
    q.doubtful_link[slot].clear();
    const SparsePairStatistic& st = p.pairs[slot];
    for (std::size_t i = 0; i < st.size(); ++i) {
      const int32_t t1 = p.aligned[1].track[st.a[i]], t2 = p.aligned[2].track[st.b[i]];
      const bool free = !assigned.count(t2);
      SparsePairStatistic& to = free ? q.doubtful[slot] : kept;
      if (free && !doubtful) continue;
      to.a.push_back(st.a[i]), to.b.push_back(st.b[i]), to.lambda.push_back(st.lambda[i]);
      to.dof.push_back(st.dof[i]), to.in_gate.push_back(free ? 0 : st.in_gate[i]);
      (free ? q.doubtful_link[slot] : kept_link).push_back(free ? 0.5 : p.link[slot][i]);
      if (free) moved[{t1, t2}] = p.link[slot][i];
    }
    q.pairs[slot] = kept;
    q.link[slot] = kept_link;
    return q;
  };
  SegmentSummary s0, sd, sf;
  const AssociationRecord r0 = join_track_segments(p, f.tracks, rec, SegmentOptions{}, &s0);
  const AssociationRecord rd =
      join_track_segments(with_free_pairs(true), f.tracks, rec, SegmentOptions{}, &sd);
  const AssociationRecord rf =
      join_track_segments(with_free_pairs(false), f.tracks, rec, SegmentOptions{}, &sf);
  const AssociationMetrics m0 = evaluate_association(f.tracks, f.sensors, r0);
  ASSERT_GT(s0.joined, 3);
  EXPECT_EQ(m0.correct, m0.targets);
  ASSERT_GT(moved.size(), 3u);

  EXPECT_EQ(sd.joined, s0.joined);
  ASSERT_EQ(rd.tuples, r0.tuples);
  int32_t checked = 0;
  for (std::size_t k = 0; k < r0.num_tuples(); ++k) {
    auto it = moved.find({r0.tuples[3 * k + 1], r0.tuples[3 * k + 2]});
    const double expected = r0.cost[k] + (it == moved.end() ? 0.0 : 0.5 - it->second);
    EXPECT_NEAR(rd.cost[k], expected, 1e-9) << "tuple " << k;
    checked += it != moved.end();
  }
  EXPECT_GT(checked, 3);

  const AssociationMetrics mf = evaluate_association(f.tracks, f.sensors, rf);
  EXPECT_LT(sf.joined, s0.joined) << "a coexisting pair outside both gates forbids the join";
  EXPECT_LT(mf.correct, m0.correct);
}

TEST(TrackSegments, ReaderRefusesBadTargetNumbers) {
  const TrackFile f = broken_file(40.0, 43.0);
  TrackFile out = f;
  store_outcome(out, associate(f, true));
  test::TempDir dir;
  auto expect_refused = [&](const std::vector<int32_t>& target, const std::string& what) {
    TrackFile bad = out;
    bad.associations[0].target = target;
    const std::string path = dir.file("bad.h5");
    write_track_file(path, bad);
    const std::string error = test::read_error(path);
    EXPECT_NE(error.find("/target"), std::string::npos) << what << ": " << error;
  };
  std::vector<int32_t> t = out.associations[0].target;
  expect_refused({t.begin(), t.end() - 1}, "a short target dataset");
  t[0] = -3;
  expect_refused(t, "a negative target number");
  t = out.associations[0].target;
  // Two tuples sharing a track (a target of several tuples) given different numbers.
  const AssociationRecord& r = out.associations[0];
  bool shared = false;
  for (std::size_t k = 0; k < r.num_tuples() && !shared; ++k)
    for (std::size_t q = k + 1; q < r.num_tuples() && !shared; ++q)
      if (r.tuples[2 * k] >= 0 && r.tuples[2 * k] == r.tuples[2 * q]) {
        t[q] = t[k] + 100000;
        shared = true;
      }
  ASSERT_TRUE(shared) << "the broken file should give a target of two tuples";
  expect_refused(t, "a track in two targets");
}

}  // namespace
}  // namespace trackassoc
