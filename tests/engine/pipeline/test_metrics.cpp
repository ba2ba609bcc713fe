// Association metrics against hand-counted cases (engine/pipeline/metrics.hpp).
#include <gtest/gtest.h>

#include "engine/pipeline/metrics.hpp"

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

}  // namespace
}  // namespace trackassoc
