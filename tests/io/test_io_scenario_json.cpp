// Scenario JSON (io/scenario_json.hpp): the embedded scenarios, exact round trips, and errors
// that name the key path.
#include <gtest/gtest.h>

#include <cmath>

#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

const std::string kScenarios = std::string(TRACKASSOC_SOURCE_DIR) + "/data/scenarios/";
constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::string error_of(const std::string& text) {
  try {
    parse_scenario_json(text, "s.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ScenarioJson, Seed000MatchesThePaper) {
  for (const auto& [file, count] : {std::pair{"seed000.json", 10}, std::pair{"seed000_20.json", 20}}) {
    const Scenario s = read_scenario_file(kScenarios + file);
    EXPECT_EQ(s.layout, StateLayout::kXY_VXVY);
    ASSERT_EQ(s.sensors.size(), 3u);
    // seed 000 §4: radars at (125,125), (235,130), (200,140) km, σρ = 170 m, σθ = 1°.
    const double x[] = {125e3, 235e3, 200e3}, y[] = {125e3, 130e3, 140e3};
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(s.sensors[i].id, i);
      EXPECT_EQ(s.sensors[i].position[0], x[i]);
      EXPECT_EQ(s.sensors[i].position[1], y[i]);
      EXPECT_EQ(s.sensors[i].sigma_range, 170.0);
      EXPECT_EQ(s.sensors[i].sigma_bearing, kDeg);
      EXPECT_EQ(s.sensors[i].p_detect, 1.0);
    }
    EXPECT_EQ(s.random_targets.count, count);
    EXPECT_EQ(s.random_targets.heading_min, 0.0);
    EXPECT_NEAR(s.random_targets.heading_max, 2 * 3.14159265358979323846, 1e-15);
    EXPECT_EQ(s.tracker.filter, "cv");
    EXPECT_FALSE(s.description.empty());
    EXPECT_EQ(parse_scenario_json(scenario_to_json(s)), s);
  }
}

Scenario full_scenario() {
  Scenario s;
  s.name = "everything";
  s.description = "unicode ω and \"quotes\"\nnew line";
  s.layout = StateLayout::kXYZ_VXVYVZ;
  s.duration = 123.456;
  s.truth_step = 0.1;
  s.seed = 18446744073709551615ull;  // the largest uint64
  for (int i = 0; i < 2; ++i) {
    Sensor sensor;
    sensor.id = 7 + 3 * i;
    sensor.position = {1.0 / 3.0, -2e5, 1234.5};
    sensor.sigma_range = 50.0 + i;
    sensor.sigma_bearing = 0.12 * kDeg;
    sensor.sigma_elevation = 0.1234567891234;  // radians that no short degree value reproduces
    sensor.period = 4.0 + 2 * i;
    sensor.offset = 0.5;
    sensor.p_detect = 0.9;
    sensor.clutter_rate = 1.5;
    sensor.reliability = 0.6;
    s.sensors.push_back(sensor);
  }
  TargetSpec t;
  t.id = 42;
  t.initial_state = {-29500, 34500, 1000, 290, -400, 0.1};
  MotionSegment a;
  a.model = MotionModel::kCoordinatedTurn;
  a.duration = 20;
  a.turn_rate = -3 * kDeg;
  MotionSegment b;
  b.model = MotionModel::kRandomManoeuvre;
  b.duration = 0;
  b.manoeuvre_period = 1;
  b.max_turn_rate = std::nextafter(0.2, 1.0);
  b.max_speed_change = 30;
  b.speed_min = 300;
  b.speed_max = 600;
  MotionSegment c;
  c.model = MotionModel::kAccelerationStep;
  c.acceleration = {0.1, -9.81, 1e-300};
  t.segments = {a, b, c};
  s.targets.push_back(t);
  MotionSegment d;
  d.model = MotionModel::kConstantAcceleration;
  s.targets.push_back(TargetSpec{43, {0, 0, 0, 0, 0, 0}, {d}});
  s.random_targets.count = 5;
  s.random_targets.area_min = {-1, -2, -3};
  s.random_targets.area_max = {1, 2, 3};
  s.random_targets.speed_min = 4;
  s.random_targets.speed_max = 1200;
  s.random_targets.heading_min = -0.7;
  s.random_targets.heading_max = 0.7;
  s.random_targets.process_noise = 0.25;
  s.tracker.filter = "imm";
  s.tracker.process_noise = 5;
  return s;
}

TEST(ScenarioJson, FullScenarioRoundTripsExactly) {
  const Scenario s = full_scenario();
  const std::string text = scenario_to_json(s);
  const Scenario back = parse_scenario_json(text);
  EXPECT_EQ(back, s);
  // Field by field for the parts where a unit conversion could lose a bit.
  EXPECT_EQ(back.sensors[0].sigma_bearing, s.sensors[0].sigma_bearing);
  EXPECT_EQ(back.sensors[0].sigma_elevation, s.sensors[0].sigma_elevation);
  EXPECT_EQ(back.targets[0].segments[0].turn_rate, s.targets[0].segments[0].turn_rate);
  EXPECT_EQ(back.targets[0].segments[1].max_turn_rate, s.targets[0].segments[1].max_turn_rate);
  EXPECT_EQ(back.seed, s.seed);
  // A nice angle is written in degrees as a short number.
  EXPECT_NE(text.find("\"sigma_bearing_deg\": 0.12"), std::string::npos) << text;
  EXPECT_NE(text.find("\"turn_rate_deg_s\": -3.0"), std::string::npos) << text;
  EXPECT_EQ(scenario_to_json(back), text);  // and writing is stable
}

TEST(ScenarioJson, RecordingManoeuvresAndFormationsRoundTripExactly) {
  Scenario s = full_scenario();
  s.recording = {0.85, 0.4, 1.0 / 3.0 + 0.5, 0.05};
  s.random_targets.manoeuvres = {true, 15, 40.5, 8, 20, 4 * kDeg, 8, 0.6};
  s.random_targets.group_size = 3;
  s.random_targets.group_spacing = 400.25;
  const std::string text = scenario_to_json(s);
  const Scenario back = parse_scenario_json(text);
  EXPECT_EQ(back, s);
  EXPECT_EQ(back.random_targets.manoeuvres.turn_rate_max, 4 * kDeg);
  EXPECT_NE(text.find("\"turn_rate_max_deg_s\": 4.0"), std::string::npos) << text;
  EXPECT_NE(text.find("\"p_seen\": 0.85"), std::string::npos) << text;
  EXPECT_EQ(scenario_to_json(back), text);
  // Manoeuvres with default values are still on after a round trip.
  s.random_targets.manoeuvres = ManoeuvreSpec{};
  s.random_targets.manoeuvres.enabled = true;
  EXPECT_EQ(parse_scenario_json(scenario_to_json(s)), s);
  // Defaults are not written, so the text of older scenarios is unchanged.
  const std::string plain = scenario_to_json(full_scenario());
  EXPECT_EQ(plain.find("recording"), std::string::npos);
  EXPECT_EQ(plain.find("manoeuvres"), std::string::npos);
  EXPECT_EQ(plain.find("group_size"), std::string::npos);
  const Scenario parsed = parse_scenario_json(
      R"({"sensors": [{}], "recording": {"p_seen": 0.5}, "random_targets": {"manoeuvres": {}}})");
  EXPECT_EQ(parsed.recording.p_seen, 0.5);
  EXPECT_EQ(parsed.recording.coverage_min, 1.0);
  EXPECT_TRUE(parsed.random_targets.manoeuvres.enabled);
  EXPECT_EQ(parsed.random_targets.manoeuvres.p_turn, ManoeuvreSpec{}.p_turn);
  EXPECT_EQ(parsed.random_targets.group_size, 1);
}

TEST(ScenarioJson, RecordedFamilyParsesAndRoundTrips) {
  for (const char* name : {"recorded_3s", "recorded_3s_long", "recorded_4s", "recorded_5s", "recorded_dense",
                           "recorded_formation", "recorded_sync", "recorded_10k", "recorded_trackers"}) {
    const Scenario s = read_scenario_file(kScenarios + name + ".json");
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.description.empty()) << name;
    EXPECT_TRUE(s.random_targets.manoeuvres.enabled) << name;
    EXPECT_EQ(parse_scenario_json(scenario_to_json(s)), s) << name;
    if (std::string(name) != "recorded_sync") {
      EXPECT_EQ(s.recording.p_seen, 0.85) << name;
      EXPECT_EQ(s.recording.false_tracks, 0.05) << name;
    } else {
      EXPECT_TRUE(s.recording.is_default());
    }
  }
}

TEST(ScenarioJson, RecordingAndManoeuvreErrorsNameTheKeyPath) {
  auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos && msg.rfind("s.json: ", 0) == 0;
  };
  const std::string head = R"({"sensors": [{}], )";
  EXPECT_PRED2(has, error_of(head + R"("recording": {"p_sen": 0.5}})"), "recording.p_sen: unknown key");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"p_trun": 0.5}}})"),
               "random_targets.manoeuvres.p_trun: unknown key");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"turn_rate_max_deg": 3}}})"),
               "random_targets.manoeuvres.turn_rate_max_deg: unknown key");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"group_sise": 3}})"),
               "random_targets.group_sise: unknown key");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"p_seen": 1.5}})"),
               "recording.p_seen: expected a finite number in [0, 1], found number 1.5");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"p_seen": -0.1}})"), "recording.p_seen");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"coverage_min": 0}})"),
               "recording.coverage_min: expected a finite number in (0, 1]");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"coverage_max": 1.2}})"), "recording.coverage_max");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"coverage_min": 0.6, "coverage_max": 0.5}})"),
               "recording.coverage_max: expected coverage_max >= coverage_min");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"false_tracks": -1}})"),
               "recording.false_tracks: expected a finite number >= 0");
  EXPECT_PRED2(has, error_of(head + R"("recording": {"false_tracks": 1000}})"), "recording.false_tracks");
  EXPECT_PRED2(has, error_of(head + R"("recording": 3})"), "recording: expected an object");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"p_turn": 2}}})"),
               "random_targets.manoeuvres.p_turn: expected a finite number in [0, 1]");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"interval_min": 0}}})"),
               "random_targets.manoeuvres.interval_min");
  EXPECT_PRED2(
      has, error_of(head + R"("random_targets": {"manoeuvres": {"interval_min": 50, "interval_max": 40}}})"),
      "random_targets.manoeuvres.interval_max: expected interval_max >= interval_min");
  EXPECT_PRED2(
      has, error_of(head + R"("random_targets": {"manoeuvres": {"duration_min": 9, "duration_max": 8}}})"),
      "random_targets.manoeuvres.duration_max");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"turn_rate_max_deg_s": -1}}})"),
               "random_targets.manoeuvres.turn_rate_max_deg_s: expected a number >= 0");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"manoeuvres": {"acceleration_max": -1}}})"),
               "random_targets.manoeuvres.acceleration_max");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"group_size": 0}})"),
               "random_targets.group_size: expected an integer in [1, 1000000]");
  EXPECT_PRED2(has, error_of(head + R"("random_targets": {"group_spacing": -5}})"),
               "random_targets.group_spacing");
}

TEST(ScenarioJson, ManyRandomAnglesRoundTripExactly) {
  Scenario s;
  s.sensors.resize(1);
  uint64_t state = 12345;
  for (int i = 0; i < 2000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double u = static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
    s.sensors[0].sigma_bearing = 1e-6 + u * (i % 2 ? 0.1 : 100.0);
    s.random_targets.heading_min = -u * 10;
    const Scenario back = parse_scenario_json(scenario_to_json(s));
    ASSERT_EQ(back.sensors[0].sigma_bearing, s.sensors[0].sigma_bearing) << i;
    ASSERT_EQ(back.random_targets.heading_min, s.random_targets.heading_min) << i;
  }
}

TEST(ScenarioJson, DefaultsFillWhatIsNotStatedAndDegreesConvert) {
  const Scenario s = parse_scenario_json(
      R"({"sensors": [{"position": [1, 2], "sigma_bearing_deg": 2}, {"id": 5, "sigma_bearing_rad": 0.5}],
          "targets": [{"position": [3, 4], "velocity": [5, 6],
                       "segments": [{"model": "ct", "turn_rate_deg_s": 90}]}]})");
  EXPECT_EQ(s.name, "unnamed");
  ASSERT_EQ(s.sensors.size(), 2u);
  EXPECT_EQ(s.sensors[0].id, 0);
  EXPECT_EQ(s.sensors[0].position, (std::array<double, 3>{1, 2, 0}));
  EXPECT_EQ(s.sensors[0].sigma_bearing, 2 * kDeg);
  EXPECT_EQ(s.sensors[0].sigma_range, Sensor{}.sigma_range);
  EXPECT_EQ(s.sensors[1].id, 5);
  EXPECT_EQ(s.sensors[1].sigma_bearing, 0.5);
  EXPECT_EQ(s.targets[0].initial_state, (std::array<double, 6>{3, 4, 0, 5, 6, 0}));
  EXPECT_EQ(s.targets[0].segments[0].model, MotionModel::kCoordinatedTurn);
  EXPECT_NEAR(s.targets[0].segments[0].turn_rate, 3.14159265358979323846 / 2, 1e-15);
}

TEST(ScenarioJson, ErrorsNameTheKeyPathAndWhatWasFound) {
  auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos && msg.rfind("s.json: ", 0) == 0;
  };
  const std::string sensor = R"({"sensors": [{}, {)";
  EXPECT_PRED2(has, error_of(sensor + R"("sigma_rang": 3}]})"), "sensors[1].sigma_rang: unknown key");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "durration": 3})"), "durration: unknown key");
  EXPECT_PRED2(has, error_of(sensor + R"("sigma_range": -3}]})"),
               "sensors[1].sigma_range: expected a finite number > 0, found number -3");
  EXPECT_PRED2(has, error_of(sensor + R"("sigma_range": "170"}]})"),
               "sensors[1].sigma_range: expected a number > 0, found string");
  EXPECT_PRED2(has, error_of(sensor + R"("sigma_bearing_deg": 0}]})"),
               "sensors[1].sigma_bearing_deg: expected a number > 0");
  EXPECT_PRED2(has, error_of(sensor + R"("sigma_bearing_deg": 1, "sigma_bearing_rad": 1}]})"), "not both");
  EXPECT_PRED2(has, error_of(sensor + R"("p_detect": 0}]})"), "p_detect: expected a finite number in (0, 1]");
  EXPECT_PRED2(has, error_of(sensor + R"("p_detect": 1.5}]})"), "p_detect");
  EXPECT_PRED2(has, error_of(sensor + R"("period": 0}]})"), "period");
  EXPECT_PRED2(has, error_of(sensor + R"("id": 1.5}]})"), "sensors[1].id: expected an integer");
  EXPECT_PRED2(has, error_of(sensor + R"("id": -1}]})"), "sensors[1].id: expected an integer in [0,");
  EXPECT_PRED2(has, error_of(sensor + R"("id": 0}]})"), "sensors[1].id: sensor id 0 is used twice");
  EXPECT_PRED2(has, error_of(sensor + R"("position": [1]}]})"),
               "position: expected an array of 2 or 3 numbers");
  EXPECT_PRED2(has, error_of(sensor + R"("position": [1, "a"]}]})"), "position[1]: expected a finite number");
  EXPECT_PRED2(has, error_of(sensor + R"("position": [1, 1e999]}]})"), "number overflow");
  EXPECT_PRED2(has, error_of(sensor + R"("reliability": true}]})"), "found boolean true");
  EXPECT_PRED2(has, error_of(R"({"sensors": []})"), "sensors: expected at least one sensor");
  EXPECT_PRED2(has, error_of(R"({"sensors": {}})"), "sensors: expected an array");
  EXPECT_PRED2(has, error_of(R"({"sensors": [3]})"), "sensors[0]: expected an object");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "layout": "4d"})"), "layout: expected \"2d\" or \"3d\"");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "layout": "3d"})"),
               "sensors[0].sigma_elevation_deg: a 3-D scenario");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "seed": -1})"), "seed: expected a non-negative integer");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "duration": 0})"), "duration");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "duration": 10, "truth_step": 20})"),
               "truth_step: expected <= duration");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "duration": 1e9, "truth_step": 1})"), "1e7");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "targets": [{"segments": [{"model": "zigzag"}]}]})"),
               "targets[0].segments[0].model: expected one of cv, ca, ct, accel_step, random_manoeuvre, "
               "found string \"zigzag\"");
  EXPECT_PRED2(
      has, error_of(R"({"sensors": [{}], "targets": [{"segments": [{"speed_min": 5, "speed_max": 4}]}]})"),
      "targets[0].segments[0].speed_max: expected >= speed_min");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "targets": [{"id": 1}, {"id": 1}]})"),
               "targets[1].id: target id 1 is used twice");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "random_targets": {"count": 20000000}})"),
               "random_targets.count");
  EXPECT_PRED2(has,
               error_of(R"({"sensors": [{}], "random_targets": {"area_min": [0, 5], "area_max": [1, 4]}})"),
               "random_targets.area_max");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "random_targets": {"process_noise": -1}})"),
               "random_targets.process_noise");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "tracker": {"filter": "ekf"}})"),
               "tracker.filter: expected one of cv, ca, ab, cs, cs-nn, imm");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "tracker": {"filtre": "cv"}})"),
               "tracker.filtre: unknown key");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], "name": "a", "name": "b"})"), "key 'name' appears twice");
  EXPECT_PRED2(has, error_of(R"({"sensors": [{}], )"), "invalid JSON");
  EXPECT_PRED2(has, error_of(""), "invalid JSON");
  EXPECT_PRED2(has, error_of("[1, 2]"), "(top level): expected an object");
  EXPECT_THROW(read_scenario_file(kScenarios + "no-such.json"), InputError);
}

}  // namespace
}  // namespace trackassoc
