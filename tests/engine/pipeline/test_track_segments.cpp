// Track segments joined to their targets (engine/pipeline/track_segments.hpp), against the
// simulator's truth: a simulated two-sensor recording in which one sensor breaks every track in
// two (the old track ends, the new one starts a few seconds later under a new number). The truth
// says which segments are one target; the checks are that
//  * without the segment pass the one-to-one assignment cannot get a broken target right (missed),
//  * with it every target is correct (evaluate_association over target numbers), each tuple's
//    members report at the same times, and every track is in exactly one target;
//  * when both sensors break at different times, a target's early and late tuples merge, each
//    member continuing from its predecessor (by hand, and end to end on targets that turn);
//  * the reader refuses bad target numbers, naming the dataset.
// Coasted tails and takeovers: test_track_segments_coasting.cpp; duplicates and doubtful pairs:
// test_track_segments_duplicates.cpp; the shared files: tests/support/track_segment_files.hpp.
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
  // A target of five tracks is not one tuple of two sensors; only the stitching (its tuples that never
  // coexist) makes one or two of them whole without the segment pass.
  EXPECT_LE(mp.correct, 2) << "a target of five tracks cannot be one tuple of two sensors";
  o.segments.enabled = true;
  const AssociationOutcome seg = make_associator(o)->associate(f);
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, seg.record);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  ASSERT_TRUE(seg.summary.segments.has_value());
  EXPECT_GT(seg.summary.segments->targets_merged, 0);
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
