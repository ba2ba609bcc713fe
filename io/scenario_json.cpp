#include "io/scenario_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "io/json_input.hpp"
#include "io/scenario_json_reader.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using namespace scenario_json_detail;
using ordered_json = nlohmann::ordered_json;

// Bounds that keep a scenario from asking for an absurd amount of work or memory.
constexpr double kMaxSteps = 1e7;  // duration / truth_step, duration / period
constexpr int64_t kMaxRandomTargets = 10'000'000;

constexpr const char* kFilters[] = {"cv", "ca", "ab", "cs", "cs-nn", "imm"};

// ---------------------------------------------------------------- reading

void read_sensor_errors(Reader& r, SensorErrors& e) {
  r.number("range_bias", e.range_bias);
  r.angle("azimuth_bias", "", e.azimuth_bias, nullptr, "");
  r.angle("elevation_bias", "", e.elevation_bias, nullptr, "");
  r.vector3("site_offset", e.site_offset);
  r.number("clock_offset", e.clock_offset);
  r.number("covariance_scale", e.covariance_scale, positive, " > 0");
  r.number("recycle_after", e.recycle_after, non_negative, " >= 0");
  r.number("swap_distance", e.swap_distance, non_negative, " >= 0");
  r.finish();
}

void read_tracker(Reader& r, LocalTrackerSpec& t);

// A sensor's own "tracker" block overrides the scenario's "tracker" key by key (`scenario_tracker`).
void read_sensor(Reader& r, Sensor& s, SensorErrors& errors, std::optional<LocalTrackerSpec>& tracker,
                 const LocalTrackerSpec& scenario_tracker, double& coverage_radius) {
  r.integer("id", s.id, 0, std::numeric_limits<int32_t>::max());
  r.vector3("position", s.position);
  r.number("sigma_range", s.sigma_range, positive, " > 0");
  r.angle("sigma_bearing", "", s.sigma_bearing, positive, " > 0");
  r.angle("sigma_elevation", "", s.sigma_elevation, non_negative, " >= 0");
  r.number("period", s.period, positive, " > 0");
  r.number("offset", s.offset, non_negative, " >= 0");
  r.number("p_detect", s.p_detect, probability, " in (0, 1]");
  r.number("clutter_rate", s.clutter_rate, non_negative, " >= 0");
  r.number("reliability", s.reliability, positive, " > 0");
  r.number("coverage_radius", coverage_radius, positive, " > 0");
  if (const json* e = r.get("errors")) {
    Reader er(*e, r.key_path("errors"), r.source());
    read_sensor_errors(er, errors);
  }
  if (const json* t = r.get("tracker")) {
    Reader tr(*t, r.key_path("tracker"), r.source());
    tracker = scenario_tracker;
    read_tracker(tr, *tracker);
  }
  r.finish();
}

void read_segment(Reader& r, MotionSegment& m) {
  if (const json* v = r.get("model")) {
    std::string names;
    bool found = false;
    for (const auto& mn : enum_names(MotionModel{})) {
      names += (names.empty() ? "" : ", ") + std::string(mn.name);
      if (v->is_string() && v->get<std::string>() == mn.name) {
        m.model = mn.value;
        found = true;
      }
    }
    if (!found) r.fail(r.key_path("model"), "expected one of " + names, *v);
  }
  r.number("duration", m.duration, non_negative, " >= 0");
  r.vector3("acceleration", m.acceleration);
  r.angle("turn_rate", "_s", m.turn_rate, nullptr, "");
  r.number("manoeuvre_period", m.manoeuvre_period, positive, " > 0");
  r.angle("max_turn_rate", "_s", m.max_turn_rate, non_negative, " >= 0");
  r.number("max_speed_change", m.max_speed_change, non_negative, " >= 0");
  r.number("speed_min", m.speed_min, non_negative, " >= 0");
  r.number("speed_max", m.speed_max, non_negative, " >= 0");
  if (m.speed_max < m.speed_min)
    throw InputError(r.source() + ": " + r.key_path("speed_max") + ": expected >= speed_min (" +
                     std::to_string(m.speed_min) + "), found " + std::to_string(m.speed_max));
  r.finish();
}

void read_target(Reader& r, TargetSpec& t) {
  r.integer("id", t.id, 0, std::numeric_limits<int32_t>::max());
  std::array<double, 3> p{t.initial_state[0], t.initial_state[1], t.initial_state[2]};
  std::array<double, 3> v{t.initial_state[3], t.initial_state[4], t.initial_state[5]};
  r.vector3("position", p);
  r.vector3("velocity", v);
  t.initial_state = {p[0], p[1], p[2], v[0], v[1], v[2]};
  if (const json* segments = r.array("segments")) {
    t.segments.clear();
    for (std::size_t i = 0; i < segments->size(); ++i) {
      Reader sr((*segments)[i], r.key_path("segments") + "[" + std::to_string(i) + "]", r.source());
      MotionSegment m;
      read_segment(sr, m);
      t.segments.push_back(m);
    }
  }
  r.finish();
}

bool coverage(double v) { return v > 0 && v <= 1; }

void read_manoeuvres(Reader& r, ManoeuvreSpec& m) {
  m.enabled = true;
  r.number("interval_min", m.interval_min, positive, " > 0");
  r.number("interval_max", m.interval_max, positive, " > 0");
  r.number("duration_min", m.duration_min, positive, " > 0");
  r.number("duration_max", m.duration_max, positive, " > 0");
  r.angle("turn_rate_max", "_s", m.turn_rate_max, non_negative, " >= 0");
  r.number("acceleration_max", m.acceleration_max, non_negative, " >= 0");
  r.number("p_turn", m.p_turn, unit_interval, " in [0, 1]");
  r.finish();
  auto bad = [&](const std::string& key, const std::string& what) {
    throw InputError(r.source() + ": " + r.key_path(key) + ": " + what);
  };
  if (m.interval_max < m.interval_min) bad("interval_max", "expected interval_max >= interval_min");
  if (m.duration_max < m.duration_min) bad("duration_max", "expected duration_max >= duration_min");
}

void read_recording(Reader& r, RecordingSpec& g) {
  r.number("p_seen", g.p_seen, unit_interval, " in [0, 1]");
  r.number("coverage_min", g.coverage_min, coverage, " in (0, 1]");
  r.number("coverage_max", g.coverage_max, coverage, " in (0, 1]");
  r.number("false_tracks", g.false_tracks, non_negative, " >= 0");
  r.finish();
  r.not_below("coverage_max", g.coverage_max, "coverage_min", g.coverage_min);
  if (g.false_tracks > 100)
    throw InputError(r.source() + ": " + r.key_path("false_tracks") +
                     ": expected at most 100 false tracks per target per sensor");
}

void read_random_targets(Reader& r, RandomTargetSpec& g) {
  r.integer("count", g.count, 0, kMaxRandomTargets);
  r.vector3("area_min", g.area_min);
  r.vector3("area_max", g.area_max);
  r.number("speed_min", g.speed_min, non_negative, " >= 0");
  r.number("speed_max", g.speed_max, non_negative, " >= 0");
  r.angle("heading_min", "", g.heading_min, nullptr, "");
  r.angle("heading_max", "", g.heading_max, nullptr, "");
  r.number("process_noise", g.process_noise, non_negative, " >= 0");
  if (const json* m = r.get("manoeuvres")) {
    Reader mr(*m, r.key_path("manoeuvres"), r.source());
    read_manoeuvres(mr, g.manoeuvres);
  }
  r.integer("group_size", g.group_size, 1, 1'000'000);
  r.number("group_spacing", g.group_spacing, non_negative, " >= 0");
  r.finish();
  auto bad = [&](const std::string& key, const std::string& what) {
    throw InputError(r.source() + ": " + r.key_path(key) + ": " + what);
  };
  for (int d = 0; d < 3; ++d)
    if (g.area_max[d] < g.area_min[d])
      bad("area_max", "expected area_max >= area_min in every coordinate, found coordinate " +
                          std::to_string(d) + " smaller");
  // Without area_min/area_max the area is the point (0, 0, 0): every target would start there, on
  // top of each other (and of any sensor placed at the origin, whose range-bearing measurements of
  // them are degenerate). Refused, so that the scenario is explained rather than its tracks.
  if (g.count > 0 && g.area_max[0] == g.area_min[0] && g.area_max[1] == g.area_min[1])
    bad("area_max",
        "the target area is the single point (" + std::to_string(g.area_min[0]) + ", " +
            std::to_string(g.area_min[1]) +
            ") (area_min and area_max default to the origin), so every random target would start there; "
            "give area_min and area_max, the corners of the area the targets start in");
  if (g.speed_max < g.speed_min) bad("speed_max", "expected speed_max >= speed_min");
  if (g.heading_max < g.heading_min) bad("heading_max", "expected heading_max >= heading_min");
}

void read_tracker(Reader& r, LocalTrackerSpec& t) {
  if (const json* v = r.get("filter")) {
    std::string names;
    bool found = false;
    for (const char* f : kFilters) {
      names += (names.empty() ? "" : ", ") + std::string(f);
      found = found || (v->is_string() && v->get<std::string>() == f);
    }
    if (!found) r.fail(r.key_path("filter"), "expected one of " + names, *v);
    t.filter = v->get<std::string>();
  }
  r.number("process_noise", t.process_noise, non_negative, " >= 0");
  r.finish();
}

// ---------------------------------------------------------------- writing

// Degrees for people, radians inside. The written degree value must convert back to the very same
// radians, so search a short decimal first, then the neighbouring doubles; fall back to radians.
std::optional<double> exact_degrees(double radians) {
  const double guess = radians / kDegToRad;
  for (int digits : {6, 9, 12, 15, 17}) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, guess);
    const double d = std::strtod(buffer, nullptr);
    if (d * kDegToRad == radians) return d;
  }
  double up = guess, down = guess;
  for (int i = 0; i < 16; ++i) {
    up = std::nextafter(up, std::numeric_limits<double>::infinity());
    down = std::nextafter(down, -std::numeric_limits<double>::infinity());
    if (up * kDegToRad == radians) return up;
    if (down * kDegToRad == radians) return down;
  }
  return std::nullopt;
}

void write_angle(ordered_json& j, const std::string& key, const std::string& suffix, double radians) {
  if (const auto d = exact_degrees(radians))
    j[key + "_deg" + suffix] = *d;
  else
    j[key + "_rad" + suffix] = radians;
}

ordered_json vector_json(const std::array<double, 3>& v) { return ordered_json::array({v[0], v[1], v[2]}); }

ordered_json tracker_json(const LocalTrackerSpec& t) {
  return {{"filter", t.filter}, {"process_noise", t.process_noise}};
}

}  // namespace

Scenario parse_scenario_json(const std::string& text, const std::string& source) {
  const json root = parse_json_input(text, source);
  Scenario s;
  Reader r(root, "", source);
  r.string("name", s.name);
  r.string("description", s.description);
  if (const json* v = r.get("layout")) {
    if (*v == "2d")
      s.layout = StateLayout::kXY_VXVY;
    else if (*v == "3d")
      s.layout = StateLayout::kXYZ_VXVYVZ;
    else
      r.fail("layout", "expected \"2d\" or \"3d\"", *v);
  }
  r.number("duration", s.duration, positive, " > 0");
  r.number("truth_step", s.truth_step, positive, " > 0");
  r.seed("seed", s.seed);
  // Before the sensors: a sensor's own tracker starts from the scenario's.
  if (const json* t = r.get("tracker")) {
    Reader tr(*t, "tracker", source);
    read_tracker(tr, s.tracker);
  }
  if (const json* sensors = r.array("sensors")) {
    for (std::size_t i = 0; i < sensors->size(); ++i) {
      Reader sr((*sensors)[i], "sensors[" + std::to_string(i) + "]", source);
      Sensor sensor;
      sensor.id = static_cast<int32_t>(i);
      SensorErrors errors;
      std::optional<LocalTrackerSpec> tracker;
      double coverage = 0.0;
      read_sensor(sr, sensor, errors, tracker, s.tracker, coverage);
      s.sensor_coverage.push_back(coverage);
      s.sensors.push_back(sensor);
      s.sensor_errors.push_back(errors);
      s.sensor_trackers.push_back(tracker);
    }
    // No sensor with errors (its own tracker): none at all, so the scenario equals one written
    // without the key.
    if (std::all_of(s.sensor_errors.begin(), s.sensor_errors.end(),
                    [](const SensorErrors& e) { return e.is_default(); }))
      s.sensor_errors.clear();
    if (std::none_of(s.sensor_trackers.begin(), s.sensor_trackers.end(),
                     [](const std::optional<LocalTrackerSpec>& t) { return t.has_value(); }))
      s.sensor_trackers.clear();
    if (std::all_of(s.sensor_coverage.begin(), s.sensor_coverage.end(), [](double c) { return c == 0.0; }))
      s.sensor_coverage.clear();
  }
  if (const json* targets = r.array("targets")) {
    for (std::size_t i = 0; i < targets->size(); ++i) {
      Reader tr((*targets)[i], "targets[" + std::to_string(i) + "]", source);
      TargetSpec target;
      target.id = static_cast<int32_t>(i);
      read_target(tr, target);
      s.targets.push_back(target);
    }
  }
  if (const json* g = r.get("random_targets")) {
    Reader gr(*g, "random_targets", source);
    read_random_targets(gr, s.random_targets);
  }
  if (const json* g = r.get("recording")) {
    Reader gr(*g, "recording", source);
    read_recording(gr, s.recording);
  }
  if (const json* g = r.get("wide_area")) {
    Reader gr(*g, "wide_area", source);
    read_wide_area(gr, s.wide_area);
  }
  r.finish();

  // Whole-scenario rules.
  auto bad = [&](const std::string& where, const std::string& what) {
    throw InputError(source + ": " + where + ": " + what);
  };
  if (s.sensors.empty()) bad("sensors", "expected at least one sensor, found none");
  if (s.truth_step > s.duration) bad("truth_step", "expected <= duration");
  if (s.duration / s.truth_step > kMaxSteps) bad("truth_step", "duration / truth_step exceeds 1e7 steps");
  std::set<int32_t> ids;
  for (std::size_t i = 0; i < s.sensors.size(); ++i) {
    const Sensor& sensor = s.sensors[i];
    const std::string where = "sensors[" + std::to_string(i) + "]";
    if (!ids.insert(sensor.id).second)
      bad(where + ".id", "sensor id " + std::to_string(sensor.id) + " is used twice");
    if (s.duration / sensor.period > kMaxSteps) bad(where + ".period", "duration / period exceeds 1e7 scans");
    if (s.layout == StateLayout::kXYZ_VXVYVZ && !(sensor.sigma_elevation > 0))
      bad(where + ".sigma_elevation_deg", "a 3-D scenario needs sigma_elevation > 0");
  }
  ids.clear();
  for (std::size_t i = 0; i < s.targets.size(); ++i)
    if (!ids.insert(s.targets[i].id).second)
      bad("targets[" + std::to_string(i) + "].id",
          "target id " + std::to_string(s.targets[i].id) + " is used twice");
  return s;
}

Scenario read_scenario_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scenario file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scenario_json(ss.str(), path);
}

std::string scenario_to_json(const Scenario& s) {
  ordered_json j;
  j["name"] = s.name;
  j["description"] = s.description;
  j["layout"] = s.layout == StateLayout::kXY_VXVY ? "2d" : "3d";
  j["duration"] = s.duration;
  j["truth_step"] = s.truth_step;
  j["seed"] = s.seed;
  j["sensors"] = ordered_json::array();
  for (const Sensor& sensor : s.sensors) {
    ordered_json o;
    o["id"] = sensor.id;
    o["position"] = vector_json(sensor.position);
    o["sigma_range"] = sensor.sigma_range;
    write_angle(o, "sigma_bearing", "", sensor.sigma_bearing);
    write_angle(o, "sigma_elevation", "", sensor.sigma_elevation);
    o["period"] = sensor.period;
    o["offset"] = sensor.offset;
    o["p_detect"] = sensor.p_detect;
    o["clutter_rate"] = sensor.clutter_rate;
    o["reliability"] = sensor.reliability;
    const std::size_t i = j["sensors"].size();
    if (i < s.sensor_errors.size() && !s.sensor_errors[i].is_default()) {
      const SensorErrors& e = s.sensor_errors[i];
      ordered_json eo;
      eo["range_bias"] = e.range_bias;
      write_angle(eo, "azimuth_bias", "", e.azimuth_bias);
      write_angle(eo, "elevation_bias", "", e.elevation_bias);
      eo["site_offset"] = vector_json(e.site_offset);
      eo["clock_offset"] = e.clock_offset;
      eo["covariance_scale"] = e.covariance_scale;
      eo["recycle_after"] = e.recycle_after;
      eo["swap_distance"] = e.swap_distance;
      o["errors"] = eo;
    }
    if (i < s.sensor_coverage.size() && s.sensor_coverage[i] > 0.0)
      o["coverage_radius"] = s.sensor_coverage[i];
    if (i < s.sensor_trackers.size() && s.sensor_trackers[i])
      o["tracker"] = tracker_json(*s.sensor_trackers[i]);
    j["sensors"].push_back(o);
  }
  j["targets"] = ordered_json::array();
  for (const TargetSpec& t : s.targets) {
    ordered_json o;
    o["id"] = t.id;
    o["position"] = vector_json({t.initial_state[0], t.initial_state[1], t.initial_state[2]});
    o["velocity"] = vector_json({t.initial_state[3], t.initial_state[4], t.initial_state[5]});
    o["segments"] = ordered_json::array();
    for (const MotionSegment& m : t.segments) {
      ordered_json g;
      g["model"] = enum_name(m.model);
      g["duration"] = m.duration;
      g["acceleration"] = vector_json(m.acceleration);
      write_angle(g, "turn_rate", "_s", m.turn_rate);
      g["manoeuvre_period"] = m.manoeuvre_period;
      write_angle(g, "max_turn_rate", "_s", m.max_turn_rate);
      g["max_speed_change"] = m.max_speed_change;
      g["speed_min"] = m.speed_min;
      g["speed_max"] = m.speed_max;
      o["segments"].push_back(g);
    }
    j["targets"].push_back(o);
  }
  const RandomTargetSpec& g = s.random_targets;
  ordered_json rt;
  rt["count"] = g.count;
  rt["area_min"] = vector_json(g.area_min);
  rt["area_max"] = vector_json(g.area_max);
  rt["speed_min"] = g.speed_min;
  rt["speed_max"] = g.speed_max;
  write_angle(rt, "heading_min", "", g.heading_min);
  write_angle(rt, "heading_max", "", g.heading_max);
  rt["process_noise"] = g.process_noise;
  // The new blocks are written only when they differ from the defaults, so the scenario text
  // (and so the output files) of scenarios that do not use them are unchanged.
  if (g.manoeuvres.enabled) {
    const ManoeuvreSpec& m = g.manoeuvres;
    ordered_json mo;
    mo["interval_min"] = m.interval_min;
    mo["interval_max"] = m.interval_max;
    mo["duration_min"] = m.duration_min;
    mo["duration_max"] = m.duration_max;
    write_angle(mo, "turn_rate_max", "_s", m.turn_rate_max);
    mo["acceleration_max"] = m.acceleration_max;
    mo["p_turn"] = m.p_turn;
    rt["manoeuvres"] = mo;
  }
  if (g.group_size != 1 || g.group_spacing != 0.0) {
    rt["group_size"] = g.group_size;
    rt["group_spacing"] = g.group_spacing;
  }
  j["random_targets"] = rt;
  j["tracker"] = tracker_json(s.tracker);
  if (!s.recording.is_default())
    j["recording"] = {{"p_seen", s.recording.p_seen},
                      {"coverage_min", s.recording.coverage_min},
                      {"coverage_max", s.recording.coverage_max},
                      {"false_tracks", s.recording.false_tracks}};
  if (!s.wide_area.is_default()) j["wide_area"] = wide_area_json(s.wide_area);
  return j.dump(2) + "\n";
}

}  // namespace trackassoc
