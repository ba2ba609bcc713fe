// Swaps at crossings (engine/pipeline/track_hygiene.hpp, split_swapped_tracks) on hand-made files,
// and the association that follows them (the segment pass's target merge,
// engine/pipeline/track_segments.hpp): two targets cross at right angles at speed v, and two keys
// of one sensor exchange them at the crossing.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

// Target 1 moves along +x, target 2 along +y, both at speed v; both pass the origin at t = 20 s.
Eigen::Vector4d target_state(int32_t target, double v, double t) {
  const double s = v * (t - 20.0);
  return target == 1 ? Eigen::Vector4d(s, 0, v, 0) : Eigen::Vector4d(0, s, 0, v);
}

// Sensor `sensor` reports keys 1 and 2 every 2 s from `t0` (0 … 40 s), position σ 100 m, velocity
// σ 10 m/s (the estimates exact). Key 1 follows target 1 and key 2 target 2, until `swap_after`
// when they exchange targets (no swap when it is past 40 s).
void add_sensor(TrackFile& f, int32_t sensor, double t0, double v, double swap_after) {
  Sensor s;
  s.id = sensor;
  s.period = 2.0;
  s.offset = t0;
  f.sensors.push_back(s);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 100.0 * 100.0, 100.0 * 100.0, 10.0 * 10.0, 10.0 * 10.0;
  for (double t = t0; t <= 40.0 + 1e-9; t += 2.0)
    for (int32_t key = 1; key <= 2; ++key) {
      const int32_t target = (t > swap_after) ? 3 - key : key;
      f.tracks.push_back(sensor, key, t, target_state(target, v, t), P, target);
    }
}

TrackFile one_sensor(double v, double swap_after) {
  TrackFile f;
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  add_sensor(f, 0, 0.0, v, swap_after);
  return f;
}

// The hand calculation of the rule at the swap (20 s → 22 s). Predicted over Δt = 2 s with
// q = σ_a² = 9, per axis C = F P Fᵀ + Q + P = [[10⁴ + 4·100 + 9·8/3 + 10⁴, 2·100 + 9·2],
// [218, 100 + 9·2 + 100]] = [[20424, 218], [218, 218]], det = 218 · 20206. The own error of
// either key is (−2v, −v) on one axis and (2v, v) on the other, so its m² = 2 · v² ·
// (218·4 − 2·218·2 + 20424) / (218 · 20206) = 2 · 20424 / 4404908 · v². The crossed errors are 0.
double own_m2_per_key(double v) { return 2.0 * 20424.0 / (218.0 * 20206.0) * v * v; }

// The speed at which the two keys' own sum reaches χ²_8(0.9999), the rule's threshold.
double critical_speed() { return std::sqrt(chi_square_quantile(0.9999, 8) / (2.0 * own_m2_per_key(1.0))); }

TEST(TrackSwaps, TheHandCalculationMatchesTheStatistic) {
  const TrackFile f = one_sensor(100.0, 20.0);
  // Rows in push order: time step k has key 1 at 2k, key 2 at 2k + 1; 20 s is k = 10.
  EXPECT_NEAR(continuation_statistic(f.tracks, 20, 22, 9.0), own_m2_per_key(100.0), 1e-9);
  EXPECT_NEAR(continuation_statistic(f.tracks, 20, 23, 9.0), 0.0, 1e-12);  // key 1 → key 2: target 1
}

TEST(TrackSwaps, ASwapJustAboveTheThresholdIsCutAndRenumbered) {
  TrackFile f = one_sensor(1.05 * critical_speed(), 20.0);
  EXPECT_EQ(split_swapped_tracks(f, TrackSplitOptions{}), 1);
  ASSERT_EQ(f.source_track.size(), f.tracks.size());
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t recorded = f.source_track[r];
    EXPECT_EQ(recorded, static_cast<int32_t>(r % 2) + 1);  // the recorded keys, kept
    // After 20 s, new numbers one above the largest (2), in key order: key 1 → 3, key 2 → 4. Each
    // number now holds one target.
    const int32_t expected = f.tracks.t[r] > 20.0 ? recorded + 2 : recorded;
    EXPECT_EQ(f.tracks.track[r], expected) << "row " << r;
  }
  std::map<int32_t, std::set<int32_t>> targets_of;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) targets_of[f.tracks.track[r]].insert(f.tracks.truth[r]);
  for (const auto& [track, targets] : targets_of) EXPECT_EQ(targets.size(), 1u) << "track " << track;
}

TEST(TrackSwaps, ASwapJustBelowTheThresholdOrNoSwapIsKept) {
  TrackFile f = one_sensor(0.95 * critical_speed(), 20.0);
  EXPECT_EQ(split_swapped_tracks(f, TrackSplitOptions{}), 0);
  EXPECT_TRUE(f.source_track.empty());
  TrackFile g = one_sensor(100.0, 1000.0);  // the same crossing, each key on its own target
  EXPECT_EQ(split_swapped_tracks(g, TrackSplitOptions{}), 0);
  TrackFile h = one_sensor(100.0, 20.0);
  TrackSplitOptions off;
  off.swaps = false;
  EXPECT_EQ(split_tracks(h, off).swaps, 0);
  EXPECT_EQ(split_tracks(h, TrackSplitOptions{}).swaps, 1);
}

TEST(TrackSwaps, AKeyThatJumpsAloneIsKept) {
  // Key 1 turns sharply at 20 s (a manoeuvre its filter shows as a jump); key 2 is far away and
  // jumps at the same time, but neither explains the other.
  TrackFile f;
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Sensor s;
  f.sensors = {s};
  const Eigen::Matrix4d P = Eigen::Vector4d(1e4, 1e4, 100, 100).asDiagonal();
  for (double t = 0; t <= 40.0 + 1e-9; t += 2.0) {
    const double u = t - 20.0;
    f.tracks.push_back(
        0, 1, t, u <= 0 ? Eigen::Vector4d(100 * u, 0, 100, 0) : Eigen::Vector4d(0, 100 * u, 0, 100), P, 1);
    f.tracks.push_back(
        0, 2, t,
        u <= 0 ? Eigen::Vector4d(50000 + 100 * u, 0, 100, 0) : Eigen::Vector4d(50000, -100 * u, 0, -100), P,
        2);
  }
  const double own = continuation_statistic(f.tracks, 20, 22, 9.0);
  EXPECT_GT(own, chi_square_quantile(0.9999, 4));  // a jump indeed
  EXPECT_EQ(split_swapped_tracks(f, TrackSplitOptions{}), 0);
}

TEST(TrackSwaps, TwoSensorsThatSwapAtOneCrossingAreSplitAndEachTargetIsOneGroup) {
  // Sensors 0 and 2 swap keys 1 and 2 at the crossing (0 at 20 s, 2 at 21 s: its scans are 1 s
  // later); sensor 1 does not. The association's tuples are one track per sensor, so each target
  // needs the segment pass's target merge: its pieces on sensors 0 and 2 follow each other.
  TrackFile f;
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  add_sensor(f, 0, 0.0, 100.0, 20.0);
  add_sensor(f, 1, 0.5, 100.0, 1000.0);
  add_sensor(f, 2, 1.0, 100.0, 21.0);
  AssociatorOptions request;
  request.registration.enabled = false;  // the reports are exact: nothing to register
  TrackFile split = f;
  const TrackSplitSummary s = split_recorded_keys(split, request);
  EXPECT_EQ(s.swaps, 2);
  const AssociationOutcome out = make_associator(request)->associate(split);
  const AssociationMetrics m = evaluate_association(split.tracks, split.sensors, out.record);
  EXPECT_EQ(m.targets, 2);
  EXPECT_EQ(m.correct, 2);
  EXPECT_EQ(m.false_tuples, 0);
  // Without the segment pass (and so its merge), the pieces of a target on sensors 0 and 2 fall
  // into two tuples: neither target is one group.
  AssociatorOptions no_segments = request;
  no_segments.segments.enabled = false;
  const AssociationOutcome apart = make_associator(no_segments)->associate(split);
  EXPECT_EQ(evaluate_association(split.tracks, split.sensors, apart.record).correct, 0);
  // Without the split, each swapped key holds both targets: neither target can be correct.
  const AssociationOutcome raw = make_associator(request)->associate(f);
  EXPECT_EQ(evaluate_association(f.tracks, f.sensors, raw.record).correct, 0);
}

}  // namespace
}  // namespace trackassoc
