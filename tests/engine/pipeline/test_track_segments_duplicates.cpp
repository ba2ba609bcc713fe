// Duplicates and doubtful pairs in the segment pass (engine/pipeline/track_segments.hpp):
//  * a duplicate (a second track of one target on one sensor at the same time) joins its target
//    only on a sensor listed in duplicate_sensors, and the duplicate statistic is the hand-worked
//    one;
//  * a doubtful pair (the family-wise veto) neither forbids a join nor is its evidence, and adds its
//    link cost, as in a tuple; a coexisting pair outside both gates forbids it.
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

}  // namespace
}  // namespace trackassoc
