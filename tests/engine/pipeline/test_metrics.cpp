// Association metrics against hand-counted cases (engine/pipeline/metrics.hpp), including a
// recycled track number split by track hygiene and scored by per-row truth.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/track_hygiene.hpp"

namespace trackassoc {
namespace {

// Three sensors (ids 10, 20, 30); sensor s holds local track numbers with given truth ids.
TrackTable make_tracks(const std::vector<std::vector<int32_t>>& truth_by_sensor) {
  TrackTable t(StateLayout::kXY_VXVY);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
  for (std::size_t s = 0; s < truth_by_sensor.size(); ++s)
    for (std::size_t k = 0; k < truth_by_sensor[s].size(); ++k)
      for (double time : {0.0, 1.0})
        t.push_back(10 * (s + 1), static_cast<int32_t>(k), time, x, P, truth_by_sensor[s][k]);
  return t;
}

std::vector<Sensor> three_sensors() {
  std::vector<Sensor> s(3);
  s[0].id = 10, s[1].id = 20, s[2].id = 30;
  return s;
}

AssociationRecord record(std::vector<std::vector<int32_t>> tuples) {
  AssociationRecord r;
  r.num_sensors = 3;
  for (auto& t : tuples) r.tuples.insert(r.tuples.end(), t.begin(), t.end());
  r.cost.assign(tuples.size(), 0.0);
  return r;
}

TEST(Metrics, AllCorrect) {
  // Track k of every sensor is target 100 + k.
  const auto tracks = make_tracks({{100, 101, 102}, {100, 101, 102}, {100, 101, 102}});
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}));
  EXPECT_TRUE(m.has_truth);
  EXPECT_EQ(m.targets, 3);
  EXPECT_EQ(m.correct, 3);
  EXPECT_DOUBLE_EQ(m.correct_rate, 1.0);
  EXPECT_DOUBLE_EQ(m.false_rate, 0.0);
}

TEST(Metrics, SwapMakesTwoFalse) {
  const auto tracks = make_tracks({{100, 101, 102}, {100, 101, 102}, {100, 101, 102}});
  // Sensor 3's tracks of targets 101 and 102 swapped: targets 101 and 102 are both false.
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 0}, {1, 1, 2}, {2, 2, 1}}));
  EXPECT_EQ(m.correct, 1);
  EXPECT_EQ(m.false_associations, 2);
  EXPECT_EQ(m.missed, 0);
  // Hand count: 3 targets, 1 correct, 2 false, 0 missed.
  EXPECT_EQ(m.targets, 3);
  EXPECT_NEAR(m.correct_rate, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(m.false_rate, 2.0 / 3.0, 1e-15);
  EXPECT_EQ(m.missed_rate, 0.0);
}

TEST(Metrics, SplitTargetIsMissed) {
  const auto tracks = make_tracks({{100, 101}, {100, 101}, {100, 101}});
  // Target 101's sensor-3 track left alone: missed, not false.
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 0}, {1, 1, -1}, {-1, -1, 1}}));
  EXPECT_EQ(m.correct, 1);
  EXPECT_EQ(m.missed, 1);
  EXPECT_EQ(m.false_associations, 0);
  EXPECT_DOUBLE_EQ(m.correct_rate, 0.5);
  EXPECT_DOUBLE_EQ(m.missed_rate, 0.5);
  EXPECT_DOUBLE_EQ(m.false_rate, 0.0);
}

TEST(Metrics, TargetSeenByTwoOfThreeIsCorrectWhenGrouped) {
  // Target 200 has no track on sensor 2; grouping its two tracks with a dummy is correct.
  const auto tracks = make_tracks({{100, 200}, {100}, {200, 100}});
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 1}, {1, -1, 0}}));
  EXPECT_EQ(m.targets, 2);
  EXPECT_EQ(m.correct, 2);
}

TEST(Metrics, TargetSeenByOneSensorDoesNotCount) {
  const auto tracks = make_tracks({{100, 300}, {100}, {100}});
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 0}, {1, -1, -1}}));
  EXPECT_EQ(m.targets, 1);
  EXPECT_EQ(m.correct, 1);
}

TEST(Metrics, NoTruthIsReported) {
  const auto tracks = make_tracks({{-1, -1}, {-1, -1}, {-1, -1}});
  const auto m = evaluate_association(tracks, three_sensors(), record({{0, 0, 0}, {1, 1, 1}}));
  EXPECT_FALSE(m.has_truth);
}

TEST(Metrics, SegmentsOfOneTargetCountAsOne) {
  // Sensor 20 broke target 100 into tracks 0 and 2; sensor 10 followed it with track 0 all along.
  // Tuples (0, 0, −1) and (0, 2, −1) of target number 7 hold all three tracks: correct. Without the
  // target numbers the same tuples split the target: missed (hand count).
  const auto tracks = make_tracks({{100, 101}, {100, 101, 100}, {}});
  AssociationRecord r = record({{0, 0, -1}, {0, 2, -1}, {1, 1, -1}});
  EXPECT_EQ(evaluate_association(tracks, three_sensors(), r).missed, 1);
  r.target = {7, 7, 8};
  const auto m = evaluate_association(tracks, three_sensors(), r);
  EXPECT_EQ(m.targets, 2);
  EXPECT_EQ(m.correct, 2);
  EXPECT_EQ(m.missed, 0);
  EXPECT_EQ(m.linked_tuples, 3);
  EXPECT_EQ(m.false_tuples, 0);
  // A target number that joins target 101's tuple to target 100's makes both false.
  r.target = {7, 7, 7};
  const auto f = evaluate_association(tracks, three_sensors(), r);
  EXPECT_EQ(f.false_associations, 2);
  EXPECT_EQ(f.correct, 0);
  // One segment left out of the target: target 100 is missed, 101 still correct.
  r = record({{0, 0, -1}, {-1, 2, -1}, {1, 1, -1}});
  r.target = {7, 9, 8};
  const auto s = evaluate_association(tracks, three_sensors(), r);
  EXPECT_EQ(s.correct, 1);
  EXPECT_EQ(s.missed, 1);
}

// Two sensors (ids 0, 1) reporting every 2 s; segments (sensor, track, truth, t0, t1, x0, y0, vx, vy)
// are straight, the last `relabel` rows of a segment carry truth `relabel_to` instead.
struct Segment {
  int32_t sensor, track, truth;
  double t0, t1, x0, y0, vx, vy;
  int relabel = 0;
  int32_t relabel_to = -1;
};

TrackFile two_sensor_file(const std::vector<Segment>& segments) {
  TrackFile f;
  f.sensors.resize(2);
  f.sensors[0].id = 0, f.sensors[1].id = 1;
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 100.0 * 100.0, 100.0 * 100.0, 10.0 * 10.0, 10.0 * 10.0;
  for (const Segment& g : segments) {
    const int n = static_cast<int>(std::lround((g.t1 - g.t0) / 2.0)) + 1;
    for (int i = 0; i < n; ++i) {
      const double dt = 2.0 * i;
      f.tracks.push_back(g.sensor, g.track, g.t0 + dt,
                         Eigen::Vector4d(g.x0 + g.vx * dt, g.y0 + g.vy * dt, g.vx, g.vy), P,
                         i >= n - g.relabel ? g.relabel_to : g.truth);
    }
  }
  return f;
}

AssociationRecord two_sensor_record(std::vector<std::array<int32_t, 2>> tuples, std::vector<int32_t> target) {
  AssociationRecord r;
  r.num_sensors = 2;
  for (const auto& t : tuples) r.tuples.insert(r.tuples.end(), t.begin(), t.end());
  r.cost.assign(tuples.size(), 0.0);
  r.target = std::move(target);
  return r;
}

// The counts of `m`: targets, correct, false, missed, linked tuples, false tuples.
void expect_counts(const AssociationMetrics& m, std::array<int32_t, 6> want, const char* what) {
  const std::array<int32_t, 6> got{m.targets, m.correct,       m.false_associations,
                                   m.missed,  m.linked_tuples, m.false_tuples};
  EXPECT_EQ(got, want) << what << " (targets, correct, false, missed, linked tuples, false tuples)";
}

TEST(Metrics, ARecycledNumberSplitByHygieneIsScoredByItsPieces) {
  // Sensor 0's track 5 follows target 1 over 0-40 s (21 rows), pauses 30 s, then target 2, 20 km
  // away, over 70-100 s (16 rows): a recycled number. Sensor 1 follows target 1 with track 1 over
  // 0-40 s (its last 3 of 21 rows mislabelled target 2: the majority, 18, is target 1) and target 2
  // with track 2 over 70-100 s.
  TrackFile f = two_sensor_file({{0, 5, 1, 0, 40, 0, 0, 200, 0},
                                 {0, 5, 2, 70, 100, 20000, 20000, 0, -150},
                                 {1, 1, 1, 0, 40, 50, 0, 200, 0, 3, 2},
                                 {1, 2, 2, 70, 100, 20050, 20000, 0, -150}});
  const TrackFile recorded = f;
  // Unsplit, key (0, 5) has 21 rows of target 1 and 16 of target 2: its target is 1, so target 2
  // has a key on sensor 1 only and needs no association. The key with both of sensor 1's tracks
  // under one target number holds target 2's key (1, 2): target 1 is false (1 target, 1 false).
  expect_counts(
      evaluate_association(recorded.tracks, recorded.sensors, two_sensor_record({{5, 1}, {5, 2}}, {0, 0})),
      {1, 0, 1, 0, 2, 1}, "unsplit, one target number");

  // Track hygiene splits (0, 5) at its jump: rows of target 2 become track 6 (one above the
  // sensor's largest number), /tracks/source_track keeps 5.
  ASSERT_EQ(split_recycled_tracks(f, TrackSplitOptions{}).cuts, 1);
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    if (f.tracks.sensor[r] == 0) {
      EXPECT_EQ(f.tracks.track[r], f.tracks.truth[r] == 1 ? 5 : 6);
      EXPECT_EQ(f.source_track[r], 5);
    }
  // Each piece in its own target's group (target numbers 0 and 1): keys of target 1 are (0, 5),
  // (1, 1); of target 2, (0, 6), (1, 2). Hand count: 2 targets, both correct, 2 linked tuples,
  // none false.
  const auto right = evaluate_association(f.tracks, f.sensors, two_sensor_record({{5, 1}, {6, 2}}, {0, 1}));
  expect_counts(right, {2, 2, 0, 0, 2, 0}, "split, each piece with its target");
  EXPECT_DOUBLE_EQ(right.correct_rate, 1.0);
  // The pieces crossed: (0, 5) with (1, 2) and (0, 6) with (1, 1): both targets false, both tuples.
  expect_counts(evaluate_association(f.tracks, f.sensors, two_sensor_record({{5, 2}, {6, 1}}, {0, 1})),
                {2, 0, 2, 0, 2, 2}, "split, pieces crossed");
  // Right tuples, but one target number over both: the group holds the keys of two targets, so
  // neither is held exactly: both false, though no tuple is (0 false tuples of 2).
  expect_counts(evaluate_association(f.tracks, f.sensors, two_sensor_record({{5, 1}, {6, 2}}, {0, 0})),
                {2, 0, 2, 0, 2, 0}, "split, one group for both targets");
  // The second piece left alone: target 1 correct, target 2 missed (its keys in two groups).
  expect_counts(
      evaluate_association(f.tracks, f.sensors, two_sensor_record({{5, 1}, {6, -1}, {-1, 2}}, {0, 1, 2})),
      {2, 1, 0, 1, 1, 0}, "split, second piece alone");
}

}  // namespace
}  // namespace trackassoc
