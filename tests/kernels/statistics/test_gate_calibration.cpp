// The calibrated gate, measured (issue 20 item 2; kernels/statistics/association_statistic.hpp).
//
// Measured here (8 runs, 40 targets; 4 runs at 150 scans), true pairs accepted / other targets
// accepted, with the lag terms of AlignmentOptions as shipped (lag_inflation 0.5, lag_look_ahead
// 1.1, lag_noise_margin 1.5): straight 1.000 at 3-150 scans, 0 of 12 480 others; turning 1.000 at
// 3 / 10 / 30 / 150 scans, 34 and 78 of 12 480 others at 3 and 10 scans and none from 30 on.
// Before the look-ahead term and the noise margin (issue 29 item 4): turning 1.000 / 1.000 /
// 1.000 / 0.988, 39 of 12 480 others at 3 scans and none from 10 on; the two terms were chosen on
// the recorded family and recorded_10k (docs/status.md), where they cut false tuples, and this
// test bounds what they cost in power. lag_inflation 0.5 was chosen here (0.3 accepts 0.60 at 30
// turning scans, 1.0 accepts 324 of 12 480 others at 3 scans), and f = 5 (f = 2 and 3 accept
// 0.89 and 0.94 at 150 turning scans).
// The seed 000 setting accepts 0.99 / 0.74 at 30 / 150 turning scans with the lag term, and
// about 0.2 without it.
//
// Same-target pairs of filtered local tracks from the simulator: two asynchronous 2-D radars
// (periods 3 s and 4 s, offsets 0.0 and 1.3 s), CV Kalman local trackers at σ = 3 m/s², straight
// and turning targets (coordinated turns of 1.5–3 deg/s at 150–300 m/s, 4–16 m/s² of true
// acceleration: well outside the trackers' motion model), 3 to 150 common scans of the 4 s grid.
// The acceptance of the true pairs at the nominal 0.99 must be at least 0.98 for every
// configuration; the χ²(n·D) gate of seed 000 is measured beside it to show why it was replaced.
// Power: the same tracks against the other targets (1.5–6 km away) must be rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "engine/pipeline/pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {
namespace {

constexpr double kPi = 3.14159265358979323846;

Scenario pair_scenario(int scans, bool turning, int targets) {
  Scenario sc;
  sc.name = "gate-calibration";
  sc.layout = StateLayout::kXY_VXVY;
  const double grid = 4.0;
  sc.duration = 20.0 + grid * (scans + 1);  // 20 s for the trackers to settle, then the common scans
  sc.truth_step = 1.0;
  sc.seed = 11;
  for (int s = 0; s < 2; ++s) {
    Sensor x;
    x.id = s;
    x.position = {s == 0 ? -60000.0 : 60000.0, -80000.0, 0.0};
    x.sigma_range = s == 0 ? 60.0 : 120.0;
    x.sigma_bearing = (s == 0 ? 0.25 : 0.4) * kPi / 180.0;
    x.period = s == 0 ? 3.0 : 4.0;
    x.offset = s == 0 ? 0.0 : 1.3;
    x.p_detect = 0.95;
    sc.sensors.push_back(x);
  }
  sc.tracker.filter = "cv";
  sc.tracker.process_noise = 3.0;
  for (int j = 0; j < targets; ++j) {
    TargetSpec t;
    t.id = j;
    const double speed = 150.0 + 150.0 * ((j * 37) % 11) / 10.0;
    const double heading = 2.0 * kPi * ((j * 13) % 17) / 17.0;
    t.initial_state = {-30000.0 + 6000.0 * (j % 10), -15000.0 + 6000.0 * (j / 10), 0.0,
                       speed * std::cos(heading),    speed * std::sin(heading),    0.0};
    MotionSegment seg;
    if (turning) {
      seg.model = MotionModel::kCoordinatedTurn;
      seg.turn_rate = ((j % 2) ? 1.0 : -1.0) * (1.5 + 1.5 * ((j * 7) % 5) / 4.0) * kPi / 180.0;
    }
    seg.duration = sc.duration;
    t.segments.push_back(seg);
    sc.targets.push_back(t);
  }
  return sc;
}

struct Acceptance {
  int pairs = 0, accepted = 0, chi2_accepted = 0, false_pairs = 0, false_accepted = 0;
  double rate() const { return pairs ? static_cast<double>(accepted) / pairs : 0.0; }
  double chi2_rate() const { return pairs ? static_cast<double>(chi2_accepted) / pairs : 0.0; }
};

Acceptance measure(int scans, bool turning, int runs) {
  Acceptance acc;
  const int targets = 40;
  const Scenario sc = pair_scenario(scans, turning, targets);
  PipelineOptions po;  // the defaults under test: two-sided alignment, union grid, calibrated gate
  // The seed 000 setting beside it: forward prediction at σ = 1 m/s² and the χ²(n·D) gate.
  const PipelineOptions paper = PipelineOptions::paper();
  for (int run = 0; run < runs; ++run) {
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, sc.seed, run));
    const std::vector<int32_t> ids{0, 1};
    std::vector<double> grid = common_time_grid(file.tracks, ids, 4.0, true);
    // Keep the last `scans` grid times (the first 20 s are the trackers' settling).
    if (static_cast<int>(grid.size()) > scans) grid.erase(grid.begin(), grid.end() - scans);
    const AlignedTracks a = align_tracks(file.tracks, 0, grid, po.alignment);
    const AlignedTracks b = align_tracks(file.tracks, 1, grid, po.alignment);
    const PairStatistic s = independent_sequential_statistic(a, b, po.statistic);
    const PairStatistic s2 = independent_sequential_statistic(
        align_tracks(file.tracks, 0, grid, paper.alignment),
        align_tracks(file.tracks, 1, grid, paper.alignment), paper.statistic);
    for (int32_t i = 0; i < a.n_tracks(); ++i)
      for (int32_t j = 0; j < b.n_tracks(); ++j) {
        const std::size_t e = static_cast<std::size_t>(i) * b.n_tracks() + j;
        if (s.dof[e] == 0) continue;
        if (a.truth[i] == b.truth[j]) {
          ++acc.pairs;
          acc.accepted += s.in_gate[e];
          acc.chi2_accepted += s2.in_gate[e];
        } else {
          ++acc.false_pairs;
          acc.false_accepted += s.in_gate[e];
        }
      }
  }
  return acc;
}

class GateCalibration : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(GateCalibration, HoldsItsNominalAcceptanceOnFilteredTracks) {
  const auto [scans, turning] = GetParam();
  const int runs = scans >= 100 ? 4 : 8;
  const Acceptance acc = measure(scans, turning, runs);
  std::printf(
      "gate calibration: %3d scans, %-8s: calibrated %.4f (%d/%d), chi2(n*D) %.4f; other targets "
      "accepted %d of %d\n",
      scans, turning ? "turning" : "straight", acc.rate(), acc.accepted, acc.pairs, acc.chi2_rate(),
      acc.false_accepted, acc.false_pairs);
  ASSERT_GE(acc.pairs, 150);
  EXPECT_GE(acc.rate(), 0.98);
  // Power: targets 6 km apart on a grid (cross-range σ ≈ 0.3–0.8 km) are told apart.
  EXPECT_LE(acc.false_accepted, acc.false_pairs / 100 + 2);
}

INSTANTIATE_TEST_SUITE_P(ScansAndMotion, GateCalibration,
                         ::testing::Combine(::testing::Values(3, 10, 30, 150), ::testing::Bool()),
                         [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) + "_scans_" +
                                  (std::get<1>(info.param) ? "turning" : "straight");
                         });

// The seed 000 setting on the same pairs (forward prediction, no lag term, χ²(n·D) gate): the
// reason for the calibrated one (docs/design.md §4.3). Through manoeuvres it rejects most true pairs.
TEST(GateCalibration, ChiSquareSumGateRejectsTruePairsOfFilteredTracks) {
  const Acceptance acc = measure(30, true, 4);
  EXPECT_LT(acc.chi2_rate(), 0.5);
  EXPECT_GE(acc.rate(), 0.98);
}

}  // namespace
}  // namespace trackassoc
