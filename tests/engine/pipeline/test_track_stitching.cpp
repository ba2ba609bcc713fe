// Fragment stitching (engine/pipeline/track_stitching.hpp) on hand-made files: a target handed over
// from one sensor to another is joined when the gap is inside the gate worked out by hand, kept
// apart just outside it, and kept apart when two successors both fit or the groups coexist.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pipeline/track_stitching.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

// Two sensors (ids 0, 1), reports every 2 s. Segments: (sensor, track, t0, t1, x at t = 0, vx);
// y = 0, vy = 0. P = diag(100², 100², 1, 1).
TrackFile hand_made(const std::vector<std::array<double, 6>>& segments) {
  TrackFile f;
  for (int32_t id : {0, 1}) {
    Sensor s;
    s.id = id;
    f.sensors.push_back(s);
  }
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  for (const auto& g : segments)
    for (double t = g[2]; t <= g[3] + 1e-9; t += 2.0)
      f.tracks.push_back(static_cast<int32_t>(g[0]), static_cast<int32_t>(g[1]), t,
                         Eigen::Vector4d(g[4] + g[5] * t, 0.0, g[5], 0.0), P, -1);
  return f;
}

// One tuple of one member per (sensor, track) given, target numbers 0, 1, ...
AssociationRecord singletons(const std::vector<std::pair<int32_t, int32_t>>& keys) {
  AssociationRecord rec;
  rec.num_sensors = 2;
  for (const auto& [sensor, track] : keys) {
    rec.tuples.push_back(sensor == 0 ? track : -1);
    rec.tuples.push_back(sensor == 1 ? track : -1);
    rec.target.push_back(static_cast<int32_t>(rec.target.size()));
  }
  return rec;
}

TrackStitchOptions no_manoeuvre() {
  TrackStitchOptions o;
  o.manoeuvre_sigma = 0.0;
  return o;
}

// By hand: sensor 0 ends at 40 s, sensor 1 starts at 60 s (Δ = 20 s), σ_a = 0. Along x the
// predicted covariance of (position, velocity) is [[1e4 + Δ², Δ], [Δ, 1]], plus the start's
// [[1e4, 0], [0, 1]]: C = [[20400, 20], [20, 2]]. A start displaced by δ along x only (same
// velocity) gives m² = δ² (C⁻¹)₀₀ = δ² · 2 / (20400 · 2 − 400) = δ² / 20200; y adds nothing.
// The gate χ²₄(0.9999) then admits |δ| ≤ sqrt(20200 · χ²) ≈ 689 m.
double critical_offset() { return std::sqrt(20200.0 * chi_square_quantile(0.9999, 4)); }

TEST(TrackStitching, AHandoverInsideTheHandComputedGateIsJoined) {
  const double delta = 0.95 * critical_offset();
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, delta, 200}});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.groups, 2);
  EXPECT_EQ(s.candidates, 1);
  EXPECT_EQ(s.stitches, 1);
  EXPECT_EQ(rec.target[1], rec.target[0]);  // the later group takes the earlier one's number
  EXPECT_EQ(rec.target[0], 0);
}

TEST(TrackStitching, AHandoverJustOutsideTheGateIsKeptApart) {
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 1.05 * critical_offset(), 200}});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}});
  EXPECT_EQ(stitch_fragments(f, rec, no_manoeuvre()).stitches, 0);
  EXPECT_NE(rec.target[1], rec.target[0]);
}

TEST(TrackStitching, TwoSuccessorsThatBothFitAreAmbiguousAndNeitherIsJoined) {
  const double d = 0.4 * critical_offset();
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, d, 200}, {1, 8, 60, 100, -d, 200}});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}, {1, 8}});
  const TrackStitchSummary s = stitch_fragments(f, rec, no_manoeuvre());
  EXPECT_EQ(s.candidates, 2);
  EXPECT_EQ(s.stitches, 0);
  EXPECT_EQ(rec.target, (std::vector<int32_t>{0, 1, 2}));
}

TEST(TrackStitching, GroupsThatCoexistAreLeftToTheAssociationAndAChainIsOneTarget) {
  // Sensor 1's track 7 reports from 30 s: it coexists with sensor 0's 0-40 s for 10 s (> 2 s).
  const TrackFile f = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 30, 100, 0, 200}});
  AssociationRecord rec = singletons({{0, 1}, {1, 7}});
  EXPECT_EQ(stitch_fragments(f, rec, no_manoeuvre()).candidates, 0);
  // A chain: 0-40 s on sensor 0, 60-100 s on sensor 1, 120-160 s on sensor 0 again (a new track).
  const TrackFile g = hand_made({{0, 1, 0, 40, 0, 200}, {1, 7, 60, 100, 0, 200}, {0, 2, 120, 160, 0, 200}});
  AssociationRecord chain = singletons({{0, 1}, {1, 7}, {0, 2}});
  EXPECT_EQ(stitch_fragments(g, chain, no_manoeuvre()).stitches, 2);
  EXPECT_EQ(chain.target, (std::vector<int32_t>{0, 0, 0}));
  // Off: nothing changes.
  AssociationRecord off = singletons({{0, 1}, {1, 7}, {0, 2}});
  TrackStitchOptions o = no_manoeuvre();
  o.enabled = false;
  EXPECT_EQ(stitch_fragments(g, off, o).stitches, 0);
  EXPECT_EQ(off.target, (std::vector<int32_t>{0, 1, 2}));
}

TEST(TrackStitching, BadOptionsNameTheField) {
  TrackStitchOptions o;
  o.max_gap_s = -1;
  try {
    o.validate();
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("stitching.max_gap_s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trackassoc
