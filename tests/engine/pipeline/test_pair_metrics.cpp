// Pair metrics of evaluate (engine/pipeline/pair_metrics.hpp) on a hand-built file whose pair
// counts are worked out by hand below.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pipeline/pair_metrics.hpp"

namespace trackassoc {
namespace {

// Two sensors, ids 10 (column 0) and 20 (column 1); each track reports at integer times
// t0, t0 + 5, ..., t1 with the truth given (a list per row when it is mixed).
TrackTable hand_built_tracks() {
  TrackTable t;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
  auto track = [&](int32_t sensor, int32_t number, double t0, double t1, std::vector<int32_t> truth) {
    std::size_t k = 0;
    for (double time = t0; time <= t1; time += 5.0, ++k)
      t.push_back(sensor, number, time, x, P, truth[std::min(k, truth.size() - 1)]);
  };
  track(10, 0, 0, 10, {1});         // target 1, [0, 10]
  track(10, 1, 20, 30, {1});        // target 1 again, [20, 30]: a fragment after 10/0
  track(10, 2, 0, 30, {2});         // target 2, [0, 30]
  track(10, 3, 5, 15, {-1});        // a false track
  track(20, 5, 5, 25, {1});         // target 1, [5, 25]: overlaps 10/0 and 10/1
  track(20, 6, 40, 50, {2});        // target 2, [40, 50]: overlaps nothing of sensor 10
  track(20, 7, 25, 35, {3, 2, 2});  // majority target 2, [25, 35]: overlaps 10/2; 20/6 follows it
  return t;
}

std::vector<Sensor> sensors() {
  Sensor a, b;
  a.id = 10;
  b.id = 20;
  return {a, b};
}

AssociationRecord output(std::vector<int32_t> target) {
  AssociationRecord r;
  r.num_sensors = 2;
  r.tuples = {0, 5, 1, -1, 2, 7, 3, 6};  // (10/0, 20/5), (10/1, -), (10/2, 20/7), (10/3, 20/6)
  r.target = std::move(target);
  return r;
}

// Coexisting pairs: target 1: (10/0, 20/5), (10/1, 20/5); target 2: (10/2, 20/7) only (20/6 starts
// at 40 > 30) -> 3. Fragment pairs: sensor 10 target 1: 10/0 -> 10/1 (20 > 10); sensor 20 target 2:
// 20/7 -> 20/6 (40 > 35) -> 2.
TEST(PairMetrics, WithTargetNumbers) {
  // Targets 0, 0, 1, 2: output targets {10/0, 10/1, 20/5}, {10/2, 20/7}, {10/3, 20/6}.
  const PairMetrics m = evaluate_pairs(hand_built_tracks(), sensors(), output({0, 0, 1, 2}));
  EXPECT_EQ(m.coexisting, 3);
  EXPECT_EQ(m.coexisting_linked, 3);
  EXPECT_EQ(m.fragments, 2);
  EXPECT_EQ(m.fragments_linked, 1);  // 10/0 -> 10/1 yes; 20/7 -> 20/6 no
  // Linked pairs: 3 in the first target (all target 1), 1 in the second (target 2), 1 in the
  // third (a false track with target 2: wrong) -> 4 of 5.
  EXPECT_EQ(m.linked_pairs, 5);
  EXPECT_EQ(m.linked_pairs_same_truth, 4);
  EXPECT_DOUBLE_EQ(m.coexisting_recall, 1.0);
  EXPECT_DOUBLE_EQ(m.fragment_recall, 0.5);
  EXPECT_DOUBLE_EQ(m.precision, 0.8);
}

TEST(PairMetrics, WithoutTargetNumbersEachTupleIsATarget) {
  // Groups {10/0, 20/5}, {10/1}, {10/2, 20/7}, {10/3, 20/6}.
  const PairMetrics m = evaluate_pairs(hand_built_tracks(), sensors(), output({}));
  EXPECT_EQ(m.coexisting, 3);
  EXPECT_EQ(m.coexisting_linked, 2);
  EXPECT_EQ(m.fragments, 2);
  EXPECT_EQ(m.fragments_linked, 0);
  EXPECT_EQ(m.linked_pairs, 3);
  EXPECT_EQ(m.linked_pairs_same_truth, 2);
  EXPECT_DOUBLE_EQ(m.precision, 2.0 / 3.0);
}

TEST(PairMetrics, ATrackInTwoTuplesJoinsThem) {
  // (10/0, 20/5) and (10/1, 20/5) without target numbers: one output target of three keys.
  AssociationRecord r;
  r.num_sensors = 2;
  r.tuples = {0, 5, 1, 5};
  const PairMetrics m = evaluate_pairs(hand_built_tracks(), sensors(), r);
  EXPECT_EQ(m.coexisting_linked, 2);
  EXPECT_EQ(m.fragments_linked, 1);
  EXPECT_EQ(m.linked_pairs, 3);
  EXPECT_EQ(m.linked_pairs_same_truth, 3);
}

TEST(PairMetrics, NothingToCountIsNaNAndStoredInTheMetricsRecord) {
  AssociationRecord r;
  r.num_sensors = 2;
  r.tuples = {0, -1};
  const PairMetrics m = evaluate_pairs(hand_built_tracks(), sensors(), r);
  EXPECT_EQ(m.linked_pairs, 0);
  EXPECT_TRUE(std::isnan(m.precision));
  MetricsRecord rec;
  add_pair_metrics(rec, evaluate_pairs(hand_built_tracks(), sensors(), output({0, 0, 1, 2})));
  EXPECT_EQ(rec.tables.at("n_coexisting_pairs"), std::vector<double>{3.0});
  EXPECT_EQ(rec.tables.at("n_fragment_linked"), std::vector<double>{1.0});
  EXPECT_EQ(rec.tables.at("pair_precision"), std::vector<double>{0.8});
}

}  // namespace
}  // namespace trackassoc
