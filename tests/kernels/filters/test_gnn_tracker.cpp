// GNN tracker (kernels/filters/gnn_tracker.hpp) and local tracking (engine/tracking/local_tracking.hpp) on
// noise-free synthetic scans whose answer is worked out by hand in each test.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>
#include <set>

#include "engine/tracking/local_tracking.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/gnn_tracker.hpp"

namespace trackassoc {
namespace {

GnnTrackerOptions test_options() {
  GnnTrackerOptions o;
  o.measurement_sigma = 1.0;
  o.process_noise = 0.5;
  o.initial_speed_sigma = 5.0;
  o.cluster_distance = 5.0;
  o.confirm_hits = 2;
  o.confirm_window = 3;
  o.delete_misses = 3;
  return o;
}

TEST(SingleLinkageClusters, ChainsWithinTheDistanceAndNumbersByFirstPlot) {
  // (0,0)-(4,0)-(8,0): neighbours 4 m apart, the ends 8 m apart: one cluster by single linkage.
  const std::vector<double> x{20, 0, 4, 8, 30}, y{0, 0, 0, 0, 0};
  EXPECT_EQ(single_linkage_clusters(x, y, 5.0), (std::vector<int32_t>{0, 1, 1, 1, 2}));
  EXPECT_EQ(single_linkage_clusters(x, y, 3.9), (std::vector<int32_t>{0, 1, 2, 3, 4}));
}

// The grid-bucketed clustering against the all-pairs union-find it replaced, on random plots with
// clumps, one far outlier (the grid's cell clamp) and distances 0, 3, 25 and 10⁴ m.
TEST(SingleLinkageClusters, GridEqualsAllPairs) {
  CounterRng rng(20261202, 5);
  std::vector<double> x, y;
  for (int i = 0; i < 400; ++i) {
    const double cx = 40.0 * rng.uniform_int(10), cy = 40.0 * rng.uniform_int(10);
    x.push_back(cx + rng.normal(0.0, 4.0));
    y.push_back(cy + rng.normal(0.0, 4.0));
  }
  x.push_back(3e9), y.push_back(-2e9);
  x.push_back(x[0]), y.push_back(y[0]);  // an exact duplicate: joins at distance 0
  for (const double d : {0.0, 3.0, 25.0, 1e4}) {
    const std::size_t m = x.size();
    std::vector<int32_t> parent(m);
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int32_t(int32_t)> find = [&](int32_t i) {
      return parent[i] == i ? i : parent[i] = find(parent[i]);
    };
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t j = i + 1; j < m; ++j)
        if (std::hypot(x[i] - x[j], y[i] - y[j]) <= d) {
          const int32_t a = find(static_cast<int32_t>(i)), b = find(static_cast<int32_t>(j));
          parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<int32_t> expected(m), root_label(m, -1);
    int32_t next = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const int32_t r = find(static_cast<int32_t>(i));
      if (root_label[r] < 0) root_label[r] = next++;
      expected[i] = root_label[r];
    }
    EXPECT_EQ(single_linkage_clusters(x, y, d), expected) << "distance " << d;
  }
}

// Many targets far apart (the gated LAP goes sparse): every target's plot is assigned to its track
// in every scan after the first (hand count: 11 scans × 300), and the sparse and the dense LAP give
// the same tracks bit for bit.
TEST(GnnTracker, ManyTargetsSparseAndDenseLapAgree) {
  CounterRng rng(20261202, 6);
  const int n = 300, scans = 12;
  std::vector<double> px(n), py(n), vx(n), vy(n);
  for (int i = 0; i < n; ++i) {
    px[i] = 100.0 * (i % 20), py[i] = 100.0 * (i / 20);
    const double h = rng.uniform(0.0, 2.0 * std::numbers::pi);
    vx[i] = 5.0 * std::cos(h), vy[i] = 5.0 * std::sin(h);
  }
  GnnTrackerOptions o = test_options();
  o.measurement_sigma = 2.0;
  o.cluster_distance = 1.0;
  GnnTrackerOptions dense = o;
  dense.lap.max_density = 0.0;
  GnnTracker a(o), b(dense);
  std::vector<GnnTrackRow> ra, rb;
  int assigned = 0;
  for (int k = 0; k < scans; ++k) {
    std::vector<double> x(n), y(n);
    for (int i = 0; i < n; ++i) {
      x[i] = px[i] + vx[i] * k + rng.normal(0.0, 2.0);
      y[i] = py[i] + vy[i] * k + rng.normal(0.0, 2.0);
    }
    assigned += a.step(k, x, y, ra).assigned;
    b.step(k, x, y, rb);
  }
  EXPECT_EQ(assigned, (scans - 1) * n);
  EXPECT_EQ(a.confirmed_count(), n);
  ASSERT_EQ(ra.size(), rb.size());
  for (std::size_t r = 0; r < ra.size(); ++r) {
    EXPECT_EQ(ra[r].track, rb[r].track);
    EXPECT_EQ(ra[r].x, rb[r].x);
  }
}

TEST(GnnTrackerOptions, ValidateNamesTheField) {
  GnnTrackerOptions o;
  o.confirm_hits = 4;  // > confirm_window 3
  try {
    o.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("confirm_hits"), std::string::npos) << e.what();
  }
  o = {};
  o.gate_probability = 1.0;
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_NO_THROW(GnnTrackerOptions{}.validate());
}

// Two stationary points 1 km apart, one scan per second:
//   P at (0, 0) detected at scans 0, 2: scans 1: hits 1, misses 1 -> 1 + (3 - 2) = 2 >= M, kept;
//   scan 2: hit, hits 2 within 3 scans -> confirmed; then missed at 3, 4, 5 -> deleted at scan 5 (K=3).
//   Q at (1000, 0) detected at scans 0, 3: at scan 2 it has 1 hit in 3 scans -> deleted; at scan 3
//   its plot starts a new tentative track.
TEST(GnnTracker, MofNConfirmationAndDeletionAfterKMisses) {
  GnnTracker tracker(test_options());
  std::vector<GnnTrackRow> rows;
  auto scan = [&](double t, std::vector<double> x, std::vector<double> y) {
    return tracker.step(t, x, y, rows);
  };
  GnnScanSummary s = scan(0, {0, 1000}, {0, 0});
  EXPECT_EQ(s.started, 2);
  s = scan(1, {}, {});
  EXPECT_EQ(s.deleted, 0);
  EXPECT_EQ(s.confirmed, 0);
  s = scan(2, {0}, {0});
  EXPECT_EQ(s.confirmed, 1);
  EXPECT_EQ(s.deleted, 1);  // Q
  EXPECT_EQ(tracker.live_tracks(), 1u);
  s = scan(3, {1000}, {0});
  EXPECT_EQ(s.started, 1);
  EXPECT_EQ(s.deleted, 0);  // P: 1 miss
  s = scan(4, {}, {});
  EXPECT_EQ(s.deleted, 0);  // P: 2 misses; Q': 1 hit in 2 scans, can still confirm
  s = scan(5, {}, {});
  EXPECT_EQ(s.deleted, 2);  // P after 3 misses, Q' with 1 hit in 3 scans
  EXPECT_EQ(tracker.live_tracks(), 0u);
  // Rows: P confirmed at scan 2, alive after scans 2, 3, 4.
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rows[k].track, 0);
    EXPECT_EQ(rows[k].t, 2.0 + static_cast<double>(k));
  }
  EXPECT_EQ(tracker.confirmed_count(), 1);
}

// Two crossing targets and clutter, scans at t = 0, 1, ..., 20:
//   A (extended): 3 plots (x, 0), (x+1, 0), (x, 1), x = -50 + 5t; one cluster, centroid
//     (x + 1/3, 1/3); detected at every scan.
//   B: one plot (0, -60 + 5t), detected at t <= 14 only. It crosses A's path at (0, 0) at t = 12,
//     two seconds after A; the closest plots of A and B are 7.07 m apart (t = 11), so no merge.
//   Clutter: one plot per scan at (200 + 37k, 300 - 53k), 65 m from the previous one (outside
//     every gate): each starts a tentative track that gets no second hit and is deleted two scans
//     later (1 hit + 0 scans left < M).
// Answer: A and B are the tracks started at t = 0 in plot order, confirmed at t = 1: numbers 0
// and 1, the only confirmations. A: rows t = 1..20 (20). B coasts at t = 15, 16 and is deleted at
// t = 17 after 3 misses: rows t = 1..16 (16). Deletions: B + the clutter tracks of t = 0..18 (19)
// = 20; alive at the end: A + the clutter of t = 19, 20.
TEST(GnnTracker, TwoCrossingTargetsAndClutter) {
  GnnTracker tracker(test_options());
  std::vector<GnnTrackRow> rows;
  int deleted = 0, confirmed = 0;
  for (int k = 0; k <= 20; ++k) {
    const double t = k, xa = -50 + 5 * t;
    std::vector<double> x{xa, xa + 1, xa}, y{0, 0, 1};
    if (k <= 14) x.push_back(0), y.push_back(-60 + 5 * t);
    x.push_back(200 + 37 * k), y.push_back(300 - 53 * k);
    const GnnScanSummary s = tracker.step(t, x, y, rows);
    EXPECT_EQ(s.clusters, k <= 14 ? 3 : 2) << "t=" << t;
    deleted += s.deleted;
    confirmed += s.confirmed;
  }
  EXPECT_EQ(confirmed, 2);
  EXPECT_EQ(tracker.confirmed_count(), 2);
  EXPECT_EQ(deleted, 20);
  EXPECT_EQ(tracker.live_tracks(), 3u);
  std::vector<GnnTrackRow> a, b;
  for (const auto& r : rows) (r.track == 0 ? a : b).push_back(r);
  ASSERT_EQ(a.size(), 20u);
  ASSERT_EQ(b.size(), 16u);
  EXPECT_EQ(a.front().t, 1.0);
  EXPECT_EQ(b.back().t, 16.0);
  for (const auto& r : b) EXPECT_EQ(r.track, 1);
  // A's track follows A's centroid; B's follows B (predicted while coasting).
  for (const auto& r : a) {
    EXPECT_NEAR(r.x[0], -50 + 5 * r.t + 1.0 / 3, 1.0) << "t=" << r.t;
    EXPECT_NEAR(r.x[1], 1.0 / 3, 1.0) << "t=" << r.t;
  }
  EXPECT_NEAR(a.back().x[2], 5.0, 0.2);
  for (const auto& r : b) {
    EXPECT_NEAR(r.x[0], 0.0, 1.0) << "t=" << r.t;
    EXPECT_NEAR(r.x[1], -60 + 5 * r.t, 1.0) << "t=" << r.t;
  }
  EXPECT_NEAR(b.back().x[3], 5.0, 0.2);
}

TEST(LocalTracking, OwnshipToWorldRotatesThenTranslates) {
  DetectionScan s;
  s.ownship_x = 10;
  s.ownship_y = 20;
  s.ownship_rotation = std::numbers::pi / 2;  // ownship axis a points along world y
  double x = 0, y = 0;
  ownship_to_world(s, 1.0, 0.0, x, y);
  EXPECT_NEAR(x, 10.0, 1e-12);
  EXPECT_NEAR(y, 21.0, 1e-12);
  ownship_to_world(s, 0.0, 2.0, x, y);
  EXPECT_NEAR(x, 8.0, 1e-12);
  EXPECT_NEAR(y, 20.0, 1e-12);
}

// A stationary target at world (100, 50) seen from an ownship moving at 2 m/s along x: the
// relative plots move, the world positions do not. Sensor 7's track is confirmed at the second
// scan and reported at scans 1..9 near (100, 50) with velocity ~0; sensor 3 sees nothing.
TEST(LocalTracking, MovingOwnshipGivesAStationaryWorldTrack) {
  std::vector<DetectionScan> scans;
  for (int k = 0; k < 10; ++k) {
    DetectionScan s;
    s.sensor = 7;
    s.t = k;
    s.ownship_x = 2.0 * k;
    s.a = {100 - 2.0 * k};
    s.b = {50};
    scans.push_back(s);
    DetectionScan e;
    e.sensor = 3;
    e.t = k;
    scans.push_back(e);
  }
  LocalTrackingOptions o;
  o.default_tracker = test_options();
  LocalTrackingSummary sum;
  const TrackTable t = track_detections(scans, o, &sum);
  ASSERT_EQ(t.size(), 9u);
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_EQ(t.sensor[i], 7);
    EXPECT_EQ(t.track[i], 0);
    EXPECT_EQ(t.t[i], static_cast<double>(i + 1));
    EXPECT_NEAR(t.state[0][i], 100.0, 1e-9);
    EXPECT_NEAR(t.state[1][i], 50.0, 1e-9);
    EXPECT_NEAR(t.state[2][i], 0.0, 1e-9);
    EXPECT_EQ(t.truth[i], -1);
  }
  ASSERT_EQ(sum.sensors.size(), 2u);
  EXPECT_EQ(sum.sensors[0].sensor, 3);
  EXPECT_EQ(sum.sensors[0].confirmed_tracks, 0);
  EXPECT_EQ(sum.sensors[1].scans, 10);
  EXPECT_EQ(sum.sensors[1].confirmed_tracks, 1);
}

}  // namespace
}  // namespace trackassoc
