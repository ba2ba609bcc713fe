// The wide-area model of the simulation (engine/simulation/simulation_widearea.hpp): coverage,
// fades that split a track, births and deaths, and the size of the embedded widearea_small.
// Numbers are worked out by hand or from the model's formulas, not read back from the code.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "engine/simulation/simulation_widearea.hpp"
#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Sensor radar(int32_t id, double x, double y, double period) {
  Sensor s;
  s.id = id;
  s.position = {x, y, 0.0};
  s.sigma_range = 50.0;
  s.sigma_bearing = 0.1 * kDeg;
  s.period = period;
  s.p_detect = 0.9;
  return s;
}

// Two radars 150 km apart with 100 km coverage; targets fly through both over 20 minutes.
Scenario network() {
  Scenario sc;
  sc.name = "wide-test";
  sc.duration = 1200.0;
  sc.truth_step = 10.0;
  sc.sensors = {radar(0, 0.0, 0.0, 4.0), radar(1, 150e3, 0.0, 6.0)};
  sc.sensor_coverage = {100e3, 100e3};
  sc.random_targets.count = 60;
  sc.random_targets.area_min = {-150e3, -150e3, 0};
  sc.random_targets.area_max = {300e3, 150e3, 0};
  sc.random_targets.speed_min = 150.0;
  sc.random_targets.speed_max = 250.0;
  sc.random_targets.process_noise = 0.05;
  sc.tracker.process_noise = 1.0;
  sc.wide_area.coast_scans = 3;
  sc.wide_area.fade_rate = 1.0 / 200.0;
  sc.wide_area.fade_duration_min = 20.0;
  sc.wide_area.fade_duration_max = 60.0;
  sc.wide_area.birth_rate = 0.05;
  sc.wide_area.lifetime_mean = 1200.0;
  return sc;
}

TEST(WideArea, NoPlotOrReportBeyondTheCoverageRadius) {
  const Scenario sc = network();
  const SimulationResult r = simulate(sc, 7);
  const std::vector<TargetTrajectory> targets = simulate_trajectories(sc, 7, 0);
  std::map<int32_t, const TargetTrajectory*> by_id;
  for (const auto& tr : targets) by_id[tr.id] = &tr;
  ASSERT_GT(r.measurements.size(), 1000u);
  double farthest = 0.0;
  for (std::size_t i = 0; i < r.measurements.size(); ++i) {
    const Sensor& s = sc.sensors[r.measurements.sensor[i]];
    const auto p = by_id.at(r.measurements.target[i])->at(r.measurements.t[i]).p;
    const double range = std::hypot(p[0] - s.position[0], p[1] - s.position[1]);
    EXPECT_LE(range, 100e3) << "plot " << i;
    farthest = std::max(farthest, range);
  }
  EXPECT_GT(farthest, 0.88 * 100e3);  // the roll-off zone is reached, so the bound is not vacuous
  ASSERT_GT(r.tracks.size(), 1000u);
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    const Sensor& s = sc.sensors[r.tracks.sensor[i]];
    const double range =
        std::hypot(r.tracks.state[0][i] - s.position[0], r.tracks.state[1][i] - s.position[1]);
    EXPECT_LE(range, 100e3) << "track report " << i;
  }
}

TEST(WideArea, CoverageGainRollsOffOverTheEdge) {
  // g = 1 inside 0.9 R, ½(1 + cos(π (r − 0.9R)/(0.1R))) up to R: ½ at 0.95 R, 0 at R and beyond.
  EXPECT_DOUBLE_EQ(coverage_gain(80e3, 100e3, 0.1), 1.0);
  EXPECT_NEAR(coverage_gain(95e3, 100e3, 0.1), 0.5, 1e-12);
  EXPECT_NEAR(coverage_gain(92.5e3, 100e3, 0.1), 0.5 * (1.0 + std::cos(std::numbers::pi / 4)), 1e-12);
  EXPECT_NEAR(coverage_gain(100e3, 100e3, 0.1), 0.0, 1e-12);
  EXPECT_EQ(coverage_gain(100.001e3, 100e3, 0.1), 0.0);
  EXPECT_EQ(coverage_gain(1e9, 0.0, 0.1), 1.0);  // no radius: unlimited
}

// One target flying east at 200 m/s past one radar (p_detect 1, period 2 s, offset 0), masked over
// [100, 160) s; coast_scans 3. Scans 100..158 see nothing: misses at 100, 102 (coasted rows) and
// 104 (deleted). Track 1: rows 2..102 (its first plot at 0 is the initialisation) = 51 rows.
// Plots again from 160: 160 initialises, rows 162..300 = 70 rows, under a new number.
TEST(WideArea, AFadeOfKnownDurationSplitsATrackIntoTwoNumbersWithOneTruth) {
  Scenario sc;
  sc.name = "mask-test";
  sc.duration = 300.0;
  sc.truth_step = 1.0;
  Sensor s = radar(4, 0.0, 0.0, 2.0);
  s.p_detect = 1.0;
  sc.sensors = {s};
  sc.sensor_coverage = {500e3};
  TargetSpec t;
  t.id = 9;
  t.initial_state = {-30e3, 40e3, 0, 200.0, 0, 0};
  sc.targets = {t};
  sc.wide_area.coast_scans = 3;
  sc.wide_area.masks = {{4, 9, 100.0, 160.0}};
  const SimulationResult r = simulate(sc, 1);
  std::map<int32_t, std::vector<double>> times;
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    EXPECT_EQ(r.tracks.truth[i], 9);
    times[r.tracks.track[i]].push_back(r.tracks.t[i]);
  }
  ASSERT_EQ(times.size(), 2u);
  const auto& a = times.begin()->second;
  const auto& b = std::next(times.begin())->second;
  EXPECT_EQ(a.size(), 51u);
  EXPECT_DOUBLE_EQ(a.front(), 2.0);
  EXPECT_DOUBLE_EQ(a.back(), 102.0);
  EXPECT_EQ(b.size(), 70u);
  EXPECT_DOUBLE_EQ(b.front(), 162.0);
  EXPECT_DOUBLE_EQ(b.back(), 300.0);
  // Without the mask: one track, 150 rows (2..300).
  sc.wide_area.masks.clear();
  const SimulationResult whole = simulate(sc, 1);
  std::set<int32_t> numbers(whole.tracks.track.begin(), whole.tracks.track.end());
  EXPECT_EQ(numbers.size(), 1u);
  EXPECT_EQ(whole.tracks.size(), 150u);
}

// Births and deaths: N(t) = N0·e^(−t/L) + λL(1 − e^(−t/L)). The born targets alive at t are
// Poisson with mean λL(1 − e^(−t/L)), the initial ones binomial (N0, e^(−t/L)); the count must
// lie within 5 standard deviations at every checked time, and the births within 5σ of λT.
TEST(WideArea, AliveTargetsFollowTheBirthAndDeathRates) {
  Scenario sc;
  sc.name = "turnover-test";
  sc.duration = 4000.0;
  sc.truth_step = 50.0;
  sc.sensors = {radar(0, 0.0, 0.0, 10.0)};
  sc.random_targets.count = 100;
  sc.random_targets.area_min = {10e3, 10e3, 0};
  sc.random_targets.area_max = {90e3, 90e3, 0};
  sc.random_targets.speed_min = sc.random_targets.speed_max = 100.0;
  const double lambda = 0.2, L = 500.0;  // stationary at λL = 100 = N0
  sc.wide_area.birth_rate = lambda;
  sc.wide_area.lifetime_mean = L;
  for (uint64_t seed : {1u, 2u}) {
    const std::vector<TargetTrajectory> targets = simulate_trajectories(sc, seed, 0);
    const double born = static_cast<double>(targets.size()) - 100.0;
    EXPECT_NEAR(born, lambda * sc.duration, 5.0 * std::sqrt(lambda * sc.duration)) << "seed " << seed;
    for (double t : {0.0, 250.0, 1000.0, 2500.0, 4000.0}) {
      int alive = 0;
      for (const auto& tr : targets) alive += tr.alive(t);
      const double q = std::exp(-t / L);
      const double mean = 100.0 * q + lambda * L * (1.0 - q);
      const double var = 100.0 * q * (1.0 - q) + lambda * L * (1.0 - q);
      EXPECT_NEAR(alive, mean, 5.0 * std::sqrt(std::max(var, 1.0))) << "seed " << seed << ", t = " << t;
    }
    // Mean lifetime of the targets that die inside the run, born early (t < 1500 s) so that
    // truncation by the end of the run is negligible (e^(−2500/500) < 1 %): ≈ L, within 5σ.
    double sum = 0.0;
    int n = 0;
    for (const auto& tr : targets)
      if (tr.born < 1500.0 && std::isfinite(tr.dies)) sum += tr.dies - tr.born, ++n;
    ASSERT_GT(n, 200);
    EXPECT_NEAR(sum / n, L, 5.0 * L / std::sqrt(n));
  }
}

TEST(WideArea, TruthRowsOnlyWhileATargetIsAlive) {
  const Scenario sc = network();
  const SimulationResult r = simulate(sc, 3);
  std::map<int32_t, const TargetTrajectory*> by_id;
  const std::vector<TargetTrajectory> targets = simulate_trajectories(sc, 3, 0);
  for (const auto& tr : targets) by_id[tr.id] = &tr;
  for (std::size_t i = 0; i < r.truth.target.size(); ++i)
    ASSERT_TRUE(by_id.at(r.truth.target[i])->alive(r.truth.t[i])) << "truth row " << i;
  // Every track row is of a target alive then, within one coasting interval (3 scans of 6 s).
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    const TargetTrajectory& tr = *by_id.at(r.tracks.truth[i]);
    EXPECT_GE(r.tracks.t[i], tr.born);
    EXPECT_LE(r.tracks.t[i], tr.dies + 18.0 + 1e-9);
  }
}

TEST(WideArea, BitIdenticalForOneAndTwoThreads) {
  const Scenario sc = network();
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    return simulate(sc, 11);
  };
  const SimulationResult a = run(1), b = run(2);
  EXPECT_EQ(a.measurements.range, b.measurements.range);
  EXPECT_EQ(a.measurements.target, b.measurements.target);
  EXPECT_EQ(a.tracks.track, b.tracks.track);
  EXPECT_EQ(a.tracks.t, b.tracks.t);
  EXPECT_EQ(a.tracks.state, b.tracks.state);
  EXPECT_EQ(a.tracks.cov, b.tracks.cov);
  EXPECT_EQ(a.truth.t, b.truth.t);
}

TEST(WideArea, FadesBreakTracksIntoMoreNumbersThanTargets) {
  // Fades of 20-60 s every ~200 s, 3 missed scans end a track: a (sensor, target) pair seen for
  // several minutes has several tracks, all with its truth.
  Scenario sc = network();
  const SimulationResult with = simulate(sc, 5);
  sc.wide_area.fade_rate = 0.0;
  const SimulationResult without = simulate(sc, 5);
  auto tracks_per_pair = [](const TrackTable& t) {
    std::set<std::pair<int32_t, int32_t>> keys, pairs;
    for (std::size_t i = 0; i < t.size(); ++i) {
      keys.insert({t.sensor[i], t.track[i]});
      pairs.insert({t.sensor[i], t.truth[i]});
    }
    return static_cast<double>(keys.size()) / static_cast<double>(pairs.size());
  };
  EXPECT_GT(tracks_per_pair(with.tracks), 1.5 * tracks_per_pair(without.tracks));
}

TEST(WideArea, WideareaSmallIsWithinItsStatedSize) {
  // widearea_small's description: ~3 × 10^4 local tracks (stated range 2.5-3.5 × 10^4), 16 radars.
  const Scenario sc = load_scenario("widearea_small");
  ASSERT_EQ(sc.sensors.size(), 16u);
  const SimulationResult r = simulate(sc, 1);
  std::set<std::pair<int32_t, int32_t>> keys;
  for (std::size_t i = 0; i < r.tracks.size(); ++i) keys.insert({r.tracks.sensor[i], r.tracks.track[i]});
  EXPECT_GE(keys.size(), 25'000u);
  EXPECT_LE(keys.size(), 35'000u);
  EXPECT_GE(r.tracks.size(), 400'000u);
  EXPECT_LE(r.tracks.size(), 800'000u);
  // The benchmark is the same network at ten times the density.
  const Scenario big = load_scenario("widearea");
  EXPECT_EQ(big.sensors, sc.sensors);
  EXPECT_EQ(big.random_targets.count, 10 * sc.random_targets.count);
}

TEST(WideArea, RejectsBadFields) {
  auto refused = [](Scenario sc, const std::string& field) {
    try {
      simulate(sc, 1);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted; expected a message naming " << field;
  };
  Scenario sc = network();
  sc.wide_area.coast_scans = 0;
  refused(sc, "scenario.wide_area.coast_scans");
  sc = network();
  sc.sensor_coverage = {100e3};
  refused(sc, "scenario.sensor_coverage");
  sc = network();
  sc.sensor_coverage[1] = -1.0;
  refused(sc, "scenario.sensors[1].coverage_radius");
  sc = network();
  sc.wide_area.lifetime_mean = 0.0;
  refused(sc, "scenario.wide_area.lifetime_mean");
  sc = network();
  sc.wide_area.fade_duration_max = 10.0;
  refused(sc, "scenario.wide_area.fade_duration_max");
  sc = network();
  sc.wide_area.masks = {{7, 0, 10.0, 20.0}};
  refused(sc, "scenario.wide_area.masks[0].sensor");
  sc = network();
  sc.sensors[0].clutter_rate = 1.0;
  sc.sensor_coverage[0] = 0.0;
  refused(sc, "scenario.sensors[0].coverage_radius");
  // JSON: the block round-trips, and a bad key is named with its path.
  sc = network();
  sc.wide_area.masks = {{0, 3, 10.0, 20.0}};
  EXPECT_EQ(parse_scenario_json(scenario_to_json(sc)), sc);
  EXPECT_THROW(parse_scenario_json(R"({"sensors": [{}], "wide_area": {"fade_rate": -1}})"), InputError);
  try {
    parse_scenario_json(R"({"sensors": [{}], "wide_area": {"masks": [{"start": 5, "end": 2}]}})", "w.json");
    ADD_FAILURE() << "accepted a mask that ends before it starts";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("w.json: wide_area.masks[0].end"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trackassoc
