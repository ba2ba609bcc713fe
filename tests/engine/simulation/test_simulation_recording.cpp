// The recording model, random manoeuvres and formations of the simulation
// (engine/simulation/simulation_recording.hpp, engine/simulation/simulation_truth.hpp): numbers worked out by
// hand from the model, not read back from the implementation.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/simulation/simulation_recording.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Scenario recording_scenario(int targets) {
  Scenario sc;
  sc.name = "recording-test";
  sc.duration = 120.0;
  sc.truth_step = 1.0;
  sc.random_targets.count = targets;
  sc.random_targets.area_min = {-20e3, -20e3, 0};
  sc.random_targets.area_max = {20e3, 20e3, 0};
  sc.random_targets.speed_min = 100;
  sc.random_targets.speed_max = 300;
  sc.random_targets.process_noise = 0.5;
  const double pos[3][2] = {{-100e3, 0}, {70e3, -90e3}, {60e3, 100e3}};
  for (int s = 0; s < 3; ++s) {
    Sensor x;
    x.id = 3 + s;
    x.position = {pos[s][0], pos[s][1], 0};
    x.sigma_range = 100.0;
    x.sigma_bearing = 0.3 * kDeg;
    x.period = 3.0 + s;
    x.offset = 0.5 + s;
    x.p_detect = 1.0;
    sc.sensors.push_back(x);
  }
  sc.tracker.process_noise = 3.0;
  return sc;
}

struct TrackSummary {
  int32_t truth = 0;
  double first = 0, last = 0;
  int rows = 0;
};
// (sensor, track) -> summary; fails if a track changes truth.
std::map<std::pair<int32_t, int32_t>, TrackSummary> summarise(const TrackTable& t) {
  std::map<std::pair<int32_t, int32_t>, TrackSummary> out;
  for (std::size_t r = 0; r < t.size(); ++r) {
    auto [it, fresh] =
        out.try_emplace({t.sensor[r], t.track[r]}, TrackSummary{t.truth[r], t.t[r], t.t[r], 0});
    EXPECT_EQ(it->second.truth, t.truth[r]) << "a local track changed target";
    it->second.first = std::min(it->second.first, t.t[r]);
    it->second.last = std::max(it->second.last, t.t[r]);
    ++it->second.rows;
  }
  return out;
}

TEST(SimulationRecording, PSeenZeroGivesNoTracks) {
  Scenario sc = recording_scenario(30);
  sc.recording.p_seen = 0.0;
  const SimulationResult r = simulate(sc, 3, 0);
  EXPECT_EQ(r.tracks.size(), 0u);
  EXPECT_EQ(r.measurements.size(), 0u);   // no clutter, no target seen
  EXPECT_EQ(r.truth.size(), 30u * 121u);  // truth is still complete
}

TEST(SimulationRecording, PSeenFractionIsBinomial) {
  Scenario sc = recording_scenario(300);
  sc.recording.p_seen = 0.7;
  const SimulationResult r = simulate(sc, 5, 1);
  const auto tracks = summarise(r.tracks);
  const double pairs = 3 * 300;
  // p_detect = 1 and full coverage: every seen (sensor, target) gives one track.
  const double fraction = static_cast<double>(tracks.size()) / pairs;
  EXPECT_NEAR(fraction, 0.7, 4 * std::sqrt(0.7 * 0.3 / pairs));
  std::set<std::pair<int32_t, int32_t>> sensor_target;
  for (const auto& [key, s] : tracks) EXPECT_TRUE(sensor_target.insert({key.first, s.truth}).second);
  // Full coverage: every track ends at its sensor's last scan, offset + ⌊(T − offset)/period⌋·period.
  for (const auto& [key, s] : tracks) {
    const Sensor& x = sc.sensors[key.first - 3];
    EXPECT_DOUBLE_EQ(s.last, x.offset + std::floor((sc.duration - x.offset) / x.period) * x.period);
  }
}

TEST(SimulationRecording, TracksLieInsideTheirWindowsAndCoverTheDrawnFraction) {
  Scenario sc = recording_scenario(100);
  sc.recording.coverage_min = 0.3;
  sc.recording.coverage_max = 0.8;
  const uint64_t seed = 9;
  const SimulationResult r = simulate(sc, seed, 2);
  const RecordingPlan plan = plan_recording(sc, simulate_trajectories(sc, seed, 2), seed, 2);
  ASSERT_TRUE(plan.active);
  const auto tracks = summarise(r.tracks);
  EXPECT_EQ(tracks.size(), 300u);  // p_seen = 1, p_detect = 1: every pair has a track
  double sum_fraction = 0;
  for (const auto& [key, s] : tracks) {
    const std::size_t si = key.first - 3;
    const double period = sc.sensors[si].period;
    const SensorRecording& rec = plan.sensors[si];
    const std::size_t j = s.truth;  // random target ids are 0..n−1, in order
    EXPECT_GE(s.first, rec.window_start[j] - 1e-9);
    EXPECT_LE(s.last, rec.window_end[j] + 1e-9);
    const double span = (s.last - s.first) / sc.duration;
    // The window is U(0.3, 0.8)·duration (≥ 5 scans); the track starts at its second plot (≤ 2
    // periods in) and its last report is ≤ 1 period before the window end.
    EXPECT_LE(span, 0.8 + 1e-9);
    EXPECT_GE(span, 0.3 - 3 * period / sc.duration);
    const double length = (rec.window_end[j] - rec.window_start[j]) / sc.duration;
    EXPECT_GE(length, 0.3 - 1e-12);
    EXPECT_LE(length, 0.8 + 1e-12);
    sum_fraction += length;
  }
  // Mean of U(0.3, 0.8) over 300 windows: 0.55 ± 4·0.144/√300.
  EXPECT_NEAR(sum_fraction / 300, 0.55, 4 * 0.5 / std::sqrt(12.0) / std::sqrt(300.0));
}

TEST(SimulationRecording, FalseTracksHaveTruthMinusOneAndAreNotInTruth) {
  Scenario sc = recording_scenario(100);
  sc.recording.false_tracks = 0.2;
  sc.recording.coverage_min = 0.5;
  const SimulationResult r = simulate(sc, 4, 0);
  const auto tracks = summarise(r.tracks);
  std::map<int32_t, int> false_per_sensor, true_per_sensor;
  std::map<int32_t, std::set<int32_t>> numbers;
  for (const auto& [key, s] : tracks) {
    ++(s.truth < 0 ? false_per_sensor : true_per_sensor)[key.first];
    numbers[key.first].insert(key.second);
    EXPECT_GE(s.rows, kMinReports);
  }
  // Poisson(0.2 · 100 = 20) false tracks per sensor: the total of 3 within 4σ of 60.
  int total_false = 0;
  for (const auto& [sensor, n] : false_per_sensor) total_false += n;
  EXPECT_NEAR(total_false, 60, 4 * std::sqrt(60.0));
  for (const auto& [sensor, n] : true_per_sensor) EXPECT_EQ(n, 100);
  // Local track numbers stay 0..n−1 per sensor.
  for (const auto& [sensor, set] : numbers) {
    EXPECT_EQ(*set.begin(), 0);
    EXPECT_EQ(*set.rbegin(), static_cast<int32_t>(set.size()) - 1);
  }
  // /truth has exactly the 100 true targets; phantom plots are marked −1 (no clutter here).
  const std::set<int32_t> truth_ids(r.truth.target.begin(), r.truth.target.end());
  EXPECT_EQ(truth_ids.size(), 100u);
  EXPECT_EQ(*truth_ids.begin(), 0);
  EXPECT_EQ(*truth_ids.rbegin(), 99);
  std::size_t phantom_plots = 0;
  for (int32_t t : r.measurements.target) {
    EXPECT_GE(t, -1);
    EXPECT_LT(t, 100);
    phantom_plots += t == -1;
  }
  EXPECT_GT(phantom_plots, 0u);
  // The file writer and reader accept it (truth −1 is "unknown").
  EXPECT_NO_THROW(simulation_to_track_file(sc, r));
}

TEST(SimulationRecording, BitIdenticalForOneAndTwoThreads) {
  Scenario sc = recording_scenario(60);
  sc.recording = {0.8, 0.4, 1.0, 0.1};
  sc.sensors[0].p_detect = 0.8;
  sc.sensors[1].clutter_rate = 2.0;
  sc.random_targets.manoeuvres.enabled = true;
  sc.random_targets.group_size = 2;
  sc.random_targets.group_spacing = 500;
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    return simulate(sc, 42, 3);
  };
  const SimulationResult a = run(1), b = run(2);
  EXPECT_EQ(a.truth.state, b.truth.state);
  EXPECT_EQ(a.measurements.range, b.measurements.range);
  EXPECT_EQ(a.measurements.target, b.measurements.target);
  EXPECT_EQ(a.tracks.track, b.tracks.track);
  EXPECT_EQ(a.tracks.truth, b.tracks.truth);
  EXPECT_EQ(a.tracks.state, b.tracks.state);
  EXPECT_EQ(a.tracks.cov, b.tracks.cov);
  EXPECT_GT(a.tracks.size(), 1000u);
}

TEST(SimulationRecording, ManoeuvresLeaveTheInitialStatesUnchanged) {
  Scenario sc = recording_scenario(20);
  const auto plain = simulate_trajectories(sc, 8, 0);
  sc.random_targets.manoeuvres.enabled = true;
  const auto manoeuvring = simulate_trajectories(sc, 8, 0);
  ASSERT_EQ(plain.size(), manoeuvring.size());
  for (std::size_t j = 0; j < plain.size(); ++j) {
    EXPECT_EQ(plain[j].id, manoeuvring[j].id);
    EXPECT_EQ(plain[j].at(0).p, manoeuvring[j].at(0).p);
    EXPECT_EQ(plain[j].at(0).v, manoeuvring[j].at(0).v);
  }
}

TEST(SimulationRecording, TurnsHaveTheirCommandedRateAndLegsTheirLength) {
  RandomTargetSpec spec;
  spec.area_max = {1000, 1000, 0};
  spec.speed_min = 150;
  spec.speed_max = 250;
  spec.manoeuvres = {true, 10, 20, 5, 8, 6 * kDeg, 5, 1.0};  // turns only
  int turns = 0;
  for (int k = 0; k < 20; ++k) {
    CounterRng rng(1, 0, k), mrng(2, 0, k);
    const auto tr = random_group_trajectories(spec, 0, 1, 600, 1.0, 2, rng, mrng).front();
    double leg_start = 0;
    for (std::size_t i = 0; i < tr.pieces.size(); ++i) {
      const TrajectoryPiece& q = tr.pieces[i];
      if (q.turn_rate == 0.0) continue;
      ++turns;
      const double rate = std::abs(q.turn_rate);
      EXPECT_GE(rate, 2 * kDeg - 1e-12);
      EXPECT_LE(rate, 6 * kDeg + 1e-12);
      const double len = q.t1 - q.t0;
      if (q.t1 < 600 - 1e-9) {
        EXPECT_GE(len, 5 - 1e-9);
        EXPECT_LE(len, 8 + 1e-9);
      }
      EXPECT_GE(q.t0 - leg_start, 10 - 1e-9);  // the straight leg before it
      EXPECT_LE(q.t0 - leg_start, 20 + 1e-9);
      leg_start = q.t1;
      // Heading change over the middle half of the turn / its time = the rate (no noise in a turn).
      const Kinematics a = tr.at(q.t0 + 0.25 * len), b = tr.at(q.t0 + 0.75 * len);
      const double dh =
          std::remainder(std::atan2(b.v[1], b.v[0]) - std::atan2(a.v[1], a.v[0]), 2 * std::numbers::pi);
      EXPECT_NEAR(dh / (0.5 * len), q.turn_rate, 1e-9);
      EXPECT_NEAR(std::hypot(a.v[0], a.v[1]), std::hypot(b.v[0], b.v[1]), 1e-9);  // speed kept
    }
  }
  EXPECT_GT(turns, 20 * 15);  // 600 s / (15 + 6.5) s ≈ 28 turns per target
}

TEST(SimulationRecording, AccelerationStepsAlongTheVelocityKeepTheSpeedInBounds) {
  RandomTargetSpec spec;
  spec.area_max = {1000, 1000, 0};
  spec.speed_min = 100;
  spec.speed_max = 200;
  spec.manoeuvres = {true, 5, 10, 10, 30, 0, 20, 0.0};  // acceleration steps only, strong
  int steps = 0;
  for (int k = 0; k < 20; ++k) {
    CounterRng rng(3, 0, k), mrng(4, 0, k);
    const auto tr = random_group_trajectories(spec, 0, 1, 900, 1.0, 2, rng, mrng).front();
    for (const TrajectoryPiece& q : tr.pieces) {
      const double a = std::hypot(q.start.a[0], q.start.a[1]);
      EXPECT_EQ(q.turn_rate, 0.0);
      if (a == 0.0) continue;
      ++steps;
      EXPECT_LE(a, 20 + 1e-9);
      // Along the velocity: a × v = 0.
      EXPECT_NEAR(q.start.a[0] * q.start.v[1] - q.start.a[1] * q.start.v[0], 0.0,
                  1e-9 * a * std::hypot(q.start.v[0], q.start.v[1]));
      for (double t : {q.t0, q.t1}) {
        const Kinematics s = tr.at(std::min(t, q.t1 - 1e-9));
        EXPECT_GE(std::hypot(s.v[0], s.v[1]), 50 - 1e-6);   // 0.5 · speed_min
        EXPECT_LE(std::hypot(s.v[0], s.v[1]), 300 + 1e-6);  // 1.5 · speed_max
      }
    }
  }
  EXPECT_GT(steps, 20 * 20);
}

TEST(SimulationRecording, FormationMembersKeepTheirSpacing) {
  for (double noise : {0.0, 2.0}) {
    Scenario sc = recording_scenario(14);  // groups of 4, 4, 4, 2
    sc.random_targets.process_noise = noise;
    sc.random_targets.group_size = 4;
    sc.random_targets.group_spacing = 400;
    sc.random_targets.manoeuvres = {true, 10, 20, 5, 15, 5 * kDeg, 8, 0.5};
    const auto tr = simulate_trajectories(sc, 6, 0);
    ASSERT_EQ(tr.size(), 14u);
    for (std::size_t g = 0; g < 14; g += 4)
      for (std::size_t j = g + 1; j < std::min<std::size_t>(g + 4, 14); ++j) {
        EXPECT_EQ(tr[j].id, static_cast<int32_t>(j));
        // Line abreast: the offset is perpendicular to the velocity at the start.
        const Kinematics a0 = tr[j - 1].at(0), b0 = tr[j].at(0);
        EXPECT_NEAR((b0.p[0] - a0.p[0]) * a0.v[0] + (b0.p[1] - a0.p[1]) * a0.v[1], 0.0, 1e-6 * 400 * 300);
        for (double t = 0; t <= sc.duration; t += 0.37) {
          const Kinematics a = tr[j - 1].at(t), b = tr[j].at(t);
          EXPECT_NEAR(std::hypot(b.p[0] - a.p[0], b.p[1] - a.p[1]), 400.0, 1e-6) << "t " << t;
        }
        EXPECT_EQ(tr[j].pieces.size(), tr[g].pieces.size());
      }
  }
}

TEST(SimulationRecording, RefusesScenariosOverTheMemoryBudget) {
  Scenario sc = recording_scenario(10'000'000);
  sc.duration = 100;
  try {
    simulate(sc, 1, 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("random_targets.count"), std::string::npos) << e.what();
  }
  sc = recording_scenario(10);
  sc.recording.coverage_max = 0.2;
  sc.recording.coverage_min = 0.5;
  EXPECT_THROW(simulate(sc, 1, 0), InputError);
  sc = recording_scenario(10);
  sc.random_targets.group_size = 0;
  EXPECT_THROW(simulate(sc, 1, 0), InputError);
}

TEST(SimulationRecording, EmbeddedRecordedScenariosLookRecorded) {
  for (const char* name : {"recorded_3s", "recorded_formation", "recorded_sync"}) {
    const Scenario sc = load_scenario(name);
    const SimulationResult r = simulate(sc, 1, 0);  // the CLI default --seed
    const auto tracks = summarise(r.tracks);
    const std::size_t targets = static_cast<std::size_t>(sc.random_targets.count);
    std::size_t false_tracks = 0, full = 0;
    for (const auto& [key, s] : tracks) {
      false_tracks += s.truth < 0;
      full += s.last - s.first > 0.9 * sc.duration;
    }
    if (std::string(name) == "recorded_sync") {
      EXPECT_EQ(tracks.size(), 3 * targets) << name;
      EXPECT_EQ(false_tracks, 0u);
    } else {
      EXPECT_LT(tracks.size(), 3 * targets) << name;  // p_seen 0.85 (and a few false tracks)
      EXPECT_GT(tracks.size(), 3 * targets / 2) << name;
      EXPECT_LT(full, tracks.size() / 2) << name;  // most tracks are shorter than the run
    }
  }
}

}  // namespace
}  // namespace trackassoc
