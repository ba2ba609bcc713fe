// Per-sensor local trackers (Scenario::sensor_trackers, kernels/core/scenario.hpp): a sensor with
// its own tracker gives, for the same measurements, exactly the tracks the scenario gives when that
// tracker is every sensor's; the JSON reads, validates and round-trips it (also through a track
// file's root attribute "scenario"); the embedded recorded_trackers runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "io/scenario_json.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/two_radar_scenario.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// two_radar_scenario for 120 s, target 0 turning 90 degrees at 3 deg/s from t = 30 s; sensor ids
// 10 and 11 (not their indices).
Scenario turning_targets() {
  Scenario sc = two_radar_scenario("sensor-trackers-test");
  sc.duration = 120.0;
  MotionSegment straight, turn;
  straight.duration = 30.0;
  turn.model = MotionModel::kCoordinatedTurn;
  turn.duration = 30.0;
  turn.turn_rate = 3.0 * kDeg;
  sc.targets[0].initial_state[3] = 250.0;
  sc.targets[0].segments = {straight, turn, MotionSegment{}};
  for (Sensor& x : sc.sensors) x.id += 10;
  sc.tracker = {"cv", 1.0};
  return sc;
}

// The rows of `sensor` in `t`, as one table.
TrackTable rows_of(const TrackTable& t, int32_t sensor) {
  TrackTable out(t.layout);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t.sensor[i] == sensor)
      out.push_back(t.sensor[i], t.track[i], t.t[i], t.state_at(i), t.cov_at(i), t.truth[i]);
  return out;
}

void expect_same_tracks(const TrackTable& a, const TrackTable& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  ASSERT_GT(a.size(), 40u) << what;
  EXPECT_EQ(a.track, b.track) << what;
  EXPECT_EQ(a.t, b.t) << what;
  EXPECT_EQ(a.state, b.state) << what;
  EXPECT_EQ(a.cov, b.cov) << what;
}

// Largest position error of target 0's track at or after `from`.
double worst_error_after(const Scenario& sc, const TrackTable& t, double from) {
  const auto trajectories = simulate_trajectories(sc, 3, 0);
  double worst = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t.truth[i] != 0 || t.t[i] < from) continue;
    const Kinematics k = trajectories.at(0).at(t.t[i]);
    worst = std::max(worst, std::hypot(t.state[0][i] - k.p[0], t.state[1][i] - k.p[1]));
  }
  return worst;
}

TEST(SensorTrackers, EachSensorGetsTheTracksItsFilterGivesAlone) {
  const LocalTrackerSpec low{"cv", 0.05}, ab{"ab", 5.0};
  Scenario mixed = turning_targets();
  mixed.sensor_trackers = {low, ab};
  Scenario all_low = turning_targets(), all_ab = turning_targets();
  all_low.tracker = low;
  all_ab.tracker = ab;
  const SimulationResult m = simulate(mixed, 3), l = simulate(all_low, 3), a = simulate(all_ab, 3);
  // Measurements do not depend on the trackers (streams keyed per sensor and target).
  EXPECT_EQ(m.measurements.range, l.measurements.range);
  expect_same_tracks(rows_of(m.tracks, 10), rows_of(l.tracks, 10), "sensor 10 = cv 0.05");
  expect_same_tracks(rows_of(m.tracks, 11), rows_of(a.tracks, 11), "sensor 11 = ab 5");
  // ... and they are not the scenario tracker's, nor each other's filter's.
  const SimulationResult plain = simulate(turning_targets(), 3);
  EXPECT_NE(rows_of(m.tracks, 10).state, rows_of(plain.tracks, 10).state);
  EXPECT_NE(rows_of(m.tracks, 11).state, rows_of(l.tracks, 11).state);
  // A nullopt entry is the scenario's tracker.
  Scenario half = turning_targets();
  half.sensor_trackers = {std::nullopt, ab};
  const SimulationResult h = simulate(half, 3);
  expect_same_tracks(rows_of(h.tracks, 10), rows_of(plain.tracks, 10), "sensor 10 = scenario's cv 1");
  // The low-noise CV filter lags the 90-degree turn (ends at t = 60 s): after it, its worst error
  // is several times the alpha-beta filter's (σ = 5 m/s² follows a 13 m/s² turn).
  const double lag_low = worst_error_after(mixed, rows_of(m.tracks, 10), 40.0);
  const double lag_ab = worst_error_after(mixed, rows_of(m.tracks, 11), 40.0);
  EXPECT_GT(lag_low, 3.0 * lag_ab) << lag_low << " m vs " << lag_ab << " m";
  RecordProperty("lag_low_m", std::to_string(lag_low));
  RecordProperty("lag_ab_m", std::to_string(lag_ab));
}

TEST(SensorTrackers, JsonReadsValidatesAndRoundTrips) {
  Scenario sc = turning_targets();
  const std::string plain = scenario_to_json(sc);
  EXPECT_EQ(plain.find("\"tracker\""), plain.rfind("\"tracker\""));  // the top-level one only
  EXPECT_TRUE(parse_scenario_json(plain).sensor_trackers.empty());
  sc.sensor_trackers = {std::nullopt, LocalTrackerSpec{"imm", 2.5}};
  const std::string text = scenario_to_json(sc);
  EXPECT_EQ(parse_scenario_json(text), sc);
  EXPECT_EQ(scenario_to_json(parse_scenario_json(text)), text);

  // A key the sensor leaves out is the top-level tracker's, whichever comes first in the file.
  const std::string key = "\"reliability\": 1.0";
  std::string own = plain;
  own.replace(own.rfind(key), key.size(), key + ", \"tracker\": {\"filter\": \"ab\"}");
  own.replace(own.find("\"process_noise\": 1.0\n  }"), 20, "\"process_noise\": 7.5");
  const Scenario parsed = parse_scenario_json(own);
  ASSERT_EQ(parsed.sensor_trackers.size(), 2u);
  EXPECT_FALSE(parsed.sensor_trackers[0].has_value());
  EXPECT_EQ(*parsed.sensor_trackers[1], (LocalTrackerSpec{"ab", 7.5}));
  EXPECT_EQ(tracker_of(parsed, 0), (LocalTrackerSpec{"cv", 7.5}));
  EXPECT_EQ(tracker_of(parsed, 1), (LocalTrackerSpec{"ab", 7.5}));

  // An unknown filter names the sensor and the field.
  std::string bad = plain;
  bad.replace(bad.rfind(key), key.size(), key + ", \"tracker\": {\"filter\": \"kalman\"}");
  try {
    parse_scenario_json(bad, "f.json");
    FAIL() << "accepted filter kalman";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("f.json: sensors[1].tracker.filter: expected one of cv, ca, ab"), std::string::npos)
        << what;
    EXPECT_NE(what.find("kalman"), std::string::npos) << what;
  }
  // The simulator refuses what the filter bank cannot run, naming the sensor.
  Scenario zero = turning_targets();
  zero.sensor_trackers = {LocalTrackerSpec{"ab", 0.0}, std::nullopt};
  try {
    simulate(zero, 1);
    FAIL() << "accepted ab with process noise 0";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("scenario.sensors[0].tracker.process_noise: ", 0), 0u) << e.what();
  }
  Scenario short_list = turning_targets();
  short_list.sensor_trackers = {LocalTrackerSpec{"cv", 1.0}};
  EXPECT_THROW(simulate(short_list, 1), InputError);
}

TEST(SensorTrackers, TrackFileRecordsTheScenarioWithItsTrackers) {
  Scenario sc = turning_targets();
  sc.sensor_trackers = {LocalTrackerSpec{"cv", 0.1}, LocalTrackerSpec{"cv", 8.0}};
  const auto path =
      std::filesystem::temp_directory_path() /
      ("sensor_trackers_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".h5");
  write_track_file(path.string(), simulation_to_track_file(sc, simulate(sc, 3)));
  const TrackFile f = read_track_file(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(parse_scenario_json(f.scenario_json), sc);
}

// Median position error of `sensor`'s reports of true targets.
double median_error(const std::vector<TargetTrajectory>& truth, const TrackTable& t, int32_t sensor) {
  std::vector<double> e;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t.sensor[i] != sensor || t.truth[i] < 0) continue;
    for (const auto& g : truth)
      if (g.id == t.truth[i])
        e.push_back(std::hypot(t.state[0][i] - g.at(t.t[i]).p[0], t.state[1][i] - g.at(t.t[i]).p[1]));
  }
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  return e[e.size() / 2];
}

TEST(SensorTrackers, RecordedTrackersGivesEachRadarItsTracker) {
  const Scenario sc = load_scenario("recorded_trackers");  // the embedded copy
  ASSERT_EQ(sc.sensors.size(), 5u);
  EXPECT_EQ(tracker_of(sc, 0), (LocalTrackerSpec{"cv", 0.1}));
  EXPECT_EQ(tracker_of(sc, 1), (LocalTrackerSpec{"cv", 8.0}));
  EXPECT_EQ(tracker_of(sc, 2), (LocalTrackerSpec{"ab", 3.0}));
  EXPECT_EQ(tracker_of(sc, 3).filter, "imm");
  EXPECT_EQ(tracker_of(sc, 4), sc.tracker);
  EXPECT_EQ(sc.tracker, (LocalTrackerSpec{"cv", 3.0}));
  EXPECT_EQ(sc.random_targets.manoeuvres.p_turn, 1.0);  // every manoeuvre a turn
  // The low-noise CV radar lags the turns: its median error is several times the others'.
  const SimulationResult r = simulate(sc, sc.seed);
  const auto truth = simulate_trajectories(sc, sc.seed, 0);
  const double low = median_error(truth, r.tracks, sc.sensors[0].id);
  for (std::size_t s = 1; s < 5; ++s) {
    const double other = median_error(truth, r.tracks, sc.sensors[s].id);
    EXPECT_GT(low, 2.0 * other) << "radar " << s << ": " << low << " m vs " << other << " m";
  }
  RecordProperty("median_error_cv_0.1_m", std::to_string(low));
}

}  // namespace
}  // namespace trackassoc
