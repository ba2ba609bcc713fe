// The sensor error model of the simulation (engine/simulation/simulation_errors.hpp): each error
// checked against the same scenario without it (the noise draws are the same) and the geometry
// worked out by hand; recycled numbers and swaps on hand-made track tables.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_errors.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "tests/support/two_radar_scenario.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Scenario two_targets() { return two_radar_scenario("errors-test"); }

double range_of(const std::array<double, 3>& site, const std::array<double, 3>& p) {
  return std::hypot(p[0] - site[0], p[1] - site[1]);
}

TEST(SimulationErrors, AllZeroErrorsAreNoErrorsInTheJsonAndTheOutput) {
  Scenario sc = two_targets();
  const std::string clean = scenario_to_json(sc);
  std::string with_zero = clean;
  const std::string key = "\"reliability\": 1.0";
  with_zero.replace(with_zero.find(key), key.size(),
                    key + ", \"errors\": {\"range_bias\": 0, \"covariance_scale\": 1}");
  const Scenario parsed = parse_scenario_json(with_zero);
  EXPECT_TRUE(parsed.sensor_errors.empty());
  EXPECT_EQ(scenario_to_json(parsed), clean);
  // Errors round-trip through the JSON.
  sc.sensor_errors.resize(2);
  sc.sensor_errors[1].range_bias = 120.0;
  sc.sensor_errors[1].azimuth_bias = 0.6 * kDeg;
  sc.sensor_errors[1].site_offset = {450, -280, 0};
  sc.sensor_errors[1].recycle_after = 30.0;
  EXPECT_EQ(parse_scenario_json(scenario_to_json(sc)), sc);
}

TEST(SimulationErrors, BiasesSiteAndClockMoveEveryPlotByTheirGeometry) {
  const Scenario clean = two_targets();
  Scenario biased = clean;
  biased.sensor_errors.resize(2);
  SensorErrors& e = biased.sensor_errors[1];
  e.range_bias = 150.0;
  e.azimuth_bias = 0.5 * kDeg;
  e.site_offset = {300, -400, 0};  // 500 m
  e.clock_offset = 1.5;
  const SimulationResult a = simulate(clean, 7), b = simulate(biased, 7);
  ASSERT_EQ(a.measurements.t.size(), b.measurements.t.size());
  CounterRng unused(1, 0, 0);
  const TargetTrajectory tr0 = scripted_trajectory(clean.targets[0], clean.duration, 2, unused);
  const TargetTrajectory tr1 = scripted_trajectory(clean.targets[1], clean.duration, 2, unused);
  const std::array<double, 3> surveyed = clean.sensors[1].position;
  const std::array<double, 3> site = {surveyed[0] + 300, surveyed[1] - 400, 0};
  int checked = 0;
  for (std::size_t i = 0; i < a.measurements.t.size(); ++i) {
    const double t = a.measurements.t[i];
    ASSERT_EQ(b.measurements.t[i], t);
    if (a.measurements.sensor[i] == 0) {  // a clean sensor: untouched
      EXPECT_EQ(a.measurements.range[i], b.measurements.range[i]);
      EXPECT_EQ(a.measurements.bearing[i], b.measurements.bearing[i]);
      continue;
    }
    const TargetTrajectory& tr = a.measurements.target[i] == 0 ? tr0 : tr1;
    // Same noise draw: reported − clean = (true range from the true site at t − Δt + Δr) − (range at t).
    const double expected_range = range_of(site, tr.at(t - 1.5).p) + 150.0 - range_of(surveyed, tr.at(t).p);
    EXPECT_NEAR(b.measurements.range[i] - a.measurements.range[i], expected_range, 1e-6) << t;
    const auto p = tr.at(t - 1.5).p, q = tr.at(t).p;
    const double expected_bearing = std::atan2(p[1] - site[1], p[0] - site[0]) + 0.5 * kDeg -
                                    std::atan2(q[1] - surveyed[1], q[0] - surveyed[0]);
    EXPECT_NEAR(std::remainder(b.measurements.bearing[i] - a.measurements.bearing[i] - expected_bearing,
                               2 * std::numbers::pi),
                0.0, 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 30);
}

TEST(SimulationErrors, CovarianceScaleMultipliesTheReportedCovarianceOnly) {
  const Scenario clean = two_targets();
  Scenario scaled = clean;
  scaled.sensor_errors.resize(2);
  scaled.sensor_errors[0].covariance_scale = 2.5;
  const SimulationResult a = simulate(clean, 3), b = simulate(scaled, 3);
  ASSERT_EQ(a.tracks.size(), b.tracks.size());
  for (std::size_t r = 0; r < a.tracks.size(); ++r) {
    for (int c = 0; c < a.tracks.dim(); ++c) EXPECT_EQ(a.tracks.state[c][r], b.tracks.state[c][r]);
    const double f = a.tracks.sensor[r] == 0 ? 2.5 : 1.0;
    for (const auto& col : {0, 2, 5}) EXPECT_DOUBLE_EQ(b.tracks.cov[col][r], f * a.tracks.cov[col][r]);
  }
}

// A hand-made table: sensor 0, one row per second for each (track, truth, first, last).
TrackTable table(const std::vector<std::array<int, 4>>& tracks) {
  TrackTable t(StateLayout::kXY_VXVY);
  for (const auto& [trk, truth, first, last] : tracks)
    for (int k = first; k <= last; ++k)
      t.push_back(0, trk, k, Eigen::Vector4d(k, 0, 1, 0), Eigen::Matrix4d::Identity(), truth);
  return t;
}

std::map<int32_t, std::vector<std::pair<double, int32_t>>> by_number(const TrackTable& t) {
  std::map<int32_t, std::vector<std::pair<double, int32_t>>> out;
  for (std::size_t r = 0; r < t.size(); ++r) out[t.track[r]].push_back({t.t[r], t.truth[r]});
  return out;
}

TEST(SimulationErrors, RecycledNumbersGoToTheFirstTrackStartingRecycleAfterTheEnd) {
  Scenario sc = two_targets();
  sc.sensor_errors.resize(2);
  sc.sensor_errors[0].recycle_after = 30.0;
  // By first report: A [0, 10] takes 0 (free from 40); C [20, 30] takes 1 (free from 60);
  // B [50, 60] takes 0 again (40 <= 50); D [55, 58] finds 1 not yet free: 2.
  TrackTable t = table({{7, 10, 0, 10}, {3, 11, 50, 60}, {5, 12, 20, 30}, {9, 13, 55, 58}});
  apply_sensor_errors(sc, {}, t);
  const auto n = by_number(t);
  ASSERT_EQ(n.size(), 3u);
  EXPECT_EQ(n.at(0).front(), (std::pair<double, int32_t>{0.0, 10}));
  EXPECT_EQ(n.at(0).back(), (std::pair<double, int32_t>{60.0, 11}));
  EXPECT_EQ(n.at(0).size(), 22u);
  EXPECT_EQ(n.at(1).front().second, 12);
  EXPECT_EQ(n.at(2).front().second, 13);
}

TEST(SimulationErrors, TracksSwapAtTheClosestApproachOfTheirTargets) {
  Scenario sc = two_targets();
  sc.duration = 20.0;
  // Target 0 along y = 0 at 10 m/s, target 1 up x = 100 at 10 m/s: both at (100, 0) at t = 10.
  sc.targets[0].initial_state = {0, 0, 0, 10, 0, 0};
  sc.targets[1].initial_state = {100, -100, 0, 0, 10, 0};
  sc.sensor_errors.resize(2);
  sc.sensor_errors[0].swap_distance = 50.0;
  CounterRng unused(1, 0, 0);
  const std::vector<TargetTrajectory> targets = {scripted_trajectory(sc.targets[0], 20, 2, unused),
                                                 scripted_trajectory(sc.targets[1], 20, 2, unused)};
  TrackTable t = table({{4, 0, 0, 20}, {8, 1, 0, 20}});
  apply_sensor_errors(sc, targets, t);
  for (std::size_t r = 0; r < t.size(); ++r) {
    const int32_t own = t.truth[r] == 0 ? 4 : 8, other = t.truth[r] == 0 ? 8 : 4;
    EXPECT_EQ(t.track[r], t.t[r] > 10.0 ? other : own) << "t = " << t.t[r];
  }
  // Too far apart: no swap.
  sc.sensor_errors[0].swap_distance = 0.5;
  sc.targets[1].initial_state = {100, -99, 0, 0, 10, 0};  // passes 1 m away
  const std::vector<TargetTrajectory> apart = {targets[0], scripted_trajectory(sc.targets[1], 20, 2, unused)};
  TrackTable u = table({{4, 0, 0, 20}, {8, 1, 0, 20}});
  apply_sensor_errors(sc, apart, u);
  for (std::size_t r = 0; r < u.size(); ++r) EXPECT_EQ(u.track[r], u.truth[r] == 0 ? 4 : 8);
}

TEST(SimulationErrors, BadErrorsNameTheField) {
  Scenario sc = two_targets();
  sc.sensor_errors.resize(2);
  sc.sensor_errors[1].covariance_scale = 0.0;
  try {
    simulate(sc, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sensors[1].errors.covariance_scale"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_scenario_json(R"({"sensors": [{"errors": {"range_bias": "x"}}]})"), InputError);
  EXPECT_THROW(parse_scenario_json(R"({"sensors": [{"errors": {"rnage_bias": 1}}]})"), InputError);
}

}  // namespace
}  // namespace trackassoc
