// Simulation and local tracking (docs/design.md §4.1): determinism across thread counts, shuffled local
// track numbers with truth kept, detection / clutter / noise statistics, exact truth kinematics,
// and consistency of the local tracks.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_tracker.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/error.hpp"
#include "kernels/filters/kalman_converted.hpp"

namespace trackassoc {
namespace {

Scenario three_radar_scenario() {
  Scenario sc;
  sc.name = "test";
  sc.duration = 60.0;
  sc.truth_step = 1.0;
  sc.random_targets.count = 20;
  sc.random_targets.area_min = {0, 0, 0};
  sc.random_targets.area_max = {50e3, 50e3, 0};
  sc.random_targets.speed_min = 100;
  sc.random_targets.speed_max = 300;
  sc.random_targets.process_noise = 1.0;
  const double pos[3][2] = {{-60e3, 0}, {110e3, 10e3}, {25e3, -80e3}};
  for (int s = 0; s < 3; ++s) {
    Sensor x;
    x.id = 10 + s;
    x.position = {pos[s][0], pos[s][1], 0};
    x.sigma_range = 100.0;
    x.sigma_bearing = 0.2 * std::numbers::pi / 180;
    x.period = 1.0 + s;
    x.offset = 0.3 * s;
    x.p_detect = 0.9;
    x.clutter_rate = 2.0;
    sc.sensors.push_back(x);
  }
  TargetSpec turn;
  turn.id = 100;
  turn.initial_state = {20e3, 20e3, 0, 200, 0, 0};
  MotionSegment cv, ct;
  cv.duration = 20;
  ct.model = MotionModel::kCoordinatedTurn;
  ct.turn_rate = 0.05;
  ct.duration = 40;
  turn.segments = {cv, ct};
  sc.targets.push_back(turn);
  return sc;
}

TEST(Simulation, BitIdenticalForOneAndTwoThreads) {
  const Scenario sc = three_radar_scenario();
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    return simulate(sc, 42, 3);
  };
  const SimulationResult a = run(1), b = run(2);
  EXPECT_EQ(a.truth.state, b.truth.state);
  EXPECT_EQ(a.measurements.range, b.measurements.range);
  EXPECT_EQ(a.measurements.bearing, b.measurements.bearing);
  EXPECT_EQ(a.measurements.target, b.measurements.target);
  EXPECT_EQ(a.tracks.track, b.tracks.track);
  EXPECT_EQ(a.tracks.state, b.tracks.state);
  EXPECT_EQ(a.tracks.cov, b.tracks.cov);
  EXPECT_GT(a.tracks.size(), 1000u);
  // Another run or seed gives other numbers.
  EXPECT_NE(simulate(sc, 42, 4).measurements.range, a.measurements.range);
  EXPECT_NE(simulate(sc, 43, 3).measurements.range, a.measurements.range);
}

TEST(Simulation, LocalTrackNumbersAreShuffledPermutationsWithTruthKept) {
  const Scenario sc = three_radar_scenario();
  const SimulationResult r = simulate(sc, 7, 0);
  std::map<int, std::map<int, int>> truth_of;  // sensor -> track -> truth
  std::map<int, std::vector<int>> order;       // sensor -> truth ids ordered by track number
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    auto [it, fresh] = truth_of[r.tracks.sensor[i]].emplace(r.tracks.track[i], r.tracks.truth[i]);
    EXPECT_EQ(it->second, r.tracks.truth[i]) << "a local track changed target";
  }
  for (auto& [sensor, m] : truth_of) {
    ASSERT_EQ(m.size(), 21u) << "every target gets a track on sensor " << sensor;
    std::set<int> numbers, truths;
    for (auto& [trk, tru] : m) {
      numbers.insert(trk);
      truths.insert(tru);
      order[sensor].push_back(tru);
    }
    EXPECT_EQ(*numbers.begin(), 0);
    EXPECT_EQ(*numbers.rbegin(), 20);
    EXPECT_EQ(truths.size(), 21u);
    // Sorted truth ids would mean the numbering was not shuffled (chance 1/21!).
    EXPECT_FALSE(std::is_sorted(order[sensor].begin(), order[sensor].end()));
  }
  EXPECT_NE(order[10], order[11]);
  EXPECT_NE(order[11], order[12]);
}

TEST(Simulation, DetectionClutterAndNoiseStatistics) {
  Scenario sc = three_radar_scenario();
  sc.sensors.resize(1);
  sc.sensors[0].p_detect = 0.7;
  sc.sensors[0].clutter_rate = 3.0;
  sc.duration = 200.0;
  const SimulationResult r = simulate(sc, 11, 0);
  const auto trajectories = simulate_trajectories(sc, 11, 0);
  const double scans = 201, opportunities = scans * 21;
  double detections = 0, clutter = 0, sum_r = 0, sum_r2 = 0, sum_b2 = 0;
  for (std::size_t i = 0; i < r.measurements.size(); ++i) {
    if (r.measurements.target[i] < 0) {
      ++clutter;
      continue;
    }
    ++detections;
    const int id = r.measurements.target[i];
    const auto& tr =
        *std::find_if(trajectories.begin(), trajectories.end(), [&](auto& x) { return x.id == id; });
    const PolarPoint q = cartesian_to_polar(2, sc.sensors[0], tr.at(r.measurements.t[i]).p);
    const double er = r.measurements.range[i] - q.range;
    const double eb = std::remainder(r.measurements.bearing[i] - q.bearing, 2 * std::numbers::pi);
    sum_r += er;
    sum_r2 += er * er;
    sum_b2 += eb * eb;
  }
  // Binomial: 4 standard deviations.
  const double p = detections / opportunities;
  EXPECT_NEAR(p, 0.7, 4 * std::sqrt(0.7 * 0.3 / opportunities));
  // Poisson: mean 3 per scan, 4 standard deviations of the mean.
  EXPECT_NEAR(clutter / scans, 3.0, 4 * std::sqrt(3.0 / scans));
  EXPECT_NEAR(sum_r / detections, 0.0, 4 * 100.0 / std::sqrt(detections));
  EXPECT_NEAR(std::sqrt(sum_r2 / detections), 100.0, 5.0);
  EXPECT_NEAR(std::sqrt(sum_b2 / detections), sc.sensors[0].sigma_bearing,
              0.05 * sc.sensors[0].sigma_bearing);
  // Clutter is not used for track formation: tracks only carry real target ids.
  for (int32_t t : r.tracks.truth) EXPECT_GE(t, 0);
}

TEST(Simulation, CoordinatedTurnTruthIsExact) {
  TargetSpec spec;
  spec.initial_state = {0, 0, 0, 100, 0, 0};
  MotionSegment ct;
  ct.model = MotionModel::kCoordinatedTurn;
  ct.turn_rate = 0.1;
  ct.duration = 100;
  spec.segments = {ct};
  CounterRng rng(1);
  const auto tr = scripted_trajectory(spec, 100, 2, rng);
  // Circle of radius v/ω = 1000 m centred at (0, 1000): after half a lap the target is at (0, 2000).
  const Kinematics half = tr.at(std::numbers::pi / 0.1);
  EXPECT_NEAR(half.p[0], 0.0, 1e-9);
  EXPECT_NEAR(half.p[1], 2000.0, 1e-9);
  EXPECT_NEAR(half.v[0], -100.0, 1e-9);
  EXPECT_NEAR(std::hypot(half.a[0], half.a[1]), 100.0 * 0.1, 1e-9);
  // Segments chain continuously: CA after CV.
  MotionSegment cv, ca;
  cv.duration = 10;
  ca.model = MotionModel::kAccelerationStep;
  ca.acceleration = {2, -1, 0};
  ca.duration = 10;
  spec.segments = {cv, ca};
  const auto tr2 = scripted_trajectory(spec, 20, 2, rng);
  const Kinematics end = tr2.at(20);
  EXPECT_NEAR(end.p[0], 100 * 20 + 0.5 * 2 * 100, 1e-9);
  EXPECT_NEAR(end.p[1], -0.5 * 100, 1e-9);
  EXPECT_NEAR(end.v[0], 120, 1e-12);
}

// With the sensor far away and small angle noise the converted measurement is nearly linear, and a
// CV tracker on white-noise-acceleration truth with the matching σ is consistent: the mean NEES of
// all reports after the first 5 scans stays near D (loosely: within [0.75·D, 1.4·D]).
double mean_local_nees(StateLayout layout, double tracker_sigma) {
  Scenario sc = three_radar_scenario();
  sc.layout = layout;
  sc.targets.clear();
  sc.random_targets.count = 200;
  sc.random_targets.area_min[2] = 1000.0;
  sc.random_targets.area_max[2] = 10000.0;
  sc.tracker.process_noise = tracker_sigma;
  sc.sensors.resize(1);
  sc.sensors[0].period = 1.0;
  sc.sensors[0].offset = 0.0;
  sc.sensors[0].clutter_rate = 0.0;
  sc.sensors[0].sigma_elevation = 0.002;
  const SimulationResult r = simulate(sc, 5, 0);
  EXPECT_EQ(r.tracks.layout, layout);
  const auto trajectories = simulate_trajectories(sc, 5, 0);
  std::map<int, const TargetTrajectory*> by_id;
  for (auto& t : trajectories) by_id[t.id] = &t;
  const int d = spatial_dim(layout);
  double nees = 0;
  int count = 0;
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    if (r.tracks.t[i] < 5.0) continue;
    const Kinematics k = by_id[r.tracks.truth[i]]->at(r.tracks.t[i]);
    Eigen::VectorXd e = r.tracks.state_at(i);
    for (int a = 0; a < d; ++a) {
      e[a] -= k.p[a];
      e[d + a] -= k.v[a];
    }
    nees += e.dot(r.tracks.cov_at(i).ldlt().solve(e));
    ++count;
  }
  return nees / count;
}

TEST(Simulation, LocalTracksAreConsistent2d) {
  const double nees = mean_local_nees(StateLayout::kXY_VXVY, 1.0);
  EXPECT_GT(nees, 0.75 * 4);
  EXPECT_LT(nees, 1.4 * 4);
  // A tracker that believes in 10× less process noise than the truth has is not.
  EXPECT_GT(mean_local_nees(StateLayout::kXY_VXVY, 0.1), 2 * 4);
}

TEST(Simulation, LocalTracksAreConsistent3d) {
  const double nees = mean_local_nees(StateLayout::kXYZ_VXVYVZ, 1.0);
  EXPECT_GT(nees, 0.75 * 6);
  EXPECT_LT(nees, 1.4 * 6);
}

TEST(Simulation, RejectsBadScenarios) {
  Scenario sc = three_radar_scenario();
  sc.sensors[1].p_detect = 1.5;
  try {
    simulate(sc, 1, 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sensors[1].p_detect"), std::string::npos) << e.what();
  }
  sc = three_radar_scenario();
  sc.sensors[0].period = 0.0;
  EXPECT_THROW(simulate(sc, 1, 0), InputError);
  sc = three_radar_scenario();
  sc.tracker.filter = "kalman?";
  EXPECT_THROW(simulate(sc, 1, 0), InputError);
}

}  // namespace
}  // namespace trackassoc
