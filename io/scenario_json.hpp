// Scenario JSON (docs/design.md §3): read, validate and write trackassoc::Scenario.
// Every field has a default (kernels/core/scenario.hpp), so a scenario file only states what differs.
// Unknown keys and duplicated keys are errors (a misspelt key must not silently fall back to a
// default); the message names the key path, e.g. "f.json: sensors[1].sigma_range: expected a
// finite number > 0, found number -3".
//
// Units: SI (m, s, m/s, m/s²) except angles, which are in degrees for people: an angle key ends in
// _deg (or _deg_s for a rate), or, equivalently, _rad (_rad_s) for radians; give one, not both.
// The writer uses degrees whenever the degree value converts back to the identical double, so
// parse(to_json(s)) == s exactly; otherwise it writes radians.
// Positions, velocities, accelerations and area corners are [x, y] or [x, y, z] (missing z = 0).
//
//   {
//     "name": "seed000",                    string
//     "description": "...",                 string, free text (where the numbers come from)
//     "layout": "2d",                       "2d" (x,y,vx,vy) or "3d" (x,y,z,vx,vy,vz)
//     "duration": 60.0,                     s, > 0
//     "truth_step": 1.0,                    s, > 0, <= duration (duration/truth_step <= 1e7)
//     "seed": 1,                            integer >= 0
//     "sensors": [ {                        at least one; ids unique
//       "id": 0,                            integer >= 0 (default: index in the array)
//       "position": [125000, 125000, 0],    m
//       "sigma_range": 170.0,               m, > 0
//       "sigma_bearing_deg": 1.0,           > 0
//       "sigma_elevation_deg": 0.0,         >= 0; > 0 required when layout is "3d"
//       "period": 2.0,                      s, > 0 (duration/period <= 1e7)
//       "offset": 0.0,                      s, >= 0, time of the first scan
//       "p_detect": 1.0,                    in (0, 1]
//       "clutter_rate": 0.0,                expected false plots per scan, >= 0
//       "reliability": 1.0,                 > 0, seed 001 weight ω
//       "coverage_radius": 350000,          m, > 0, optional: no plot beyond it (wide area, below)
//       "errors": {                         optional: what the sensor adds beyond noise (docs/design.md
//       §4.10;
//                                           engine/simulation/simulation_errors.hpp has the model)
//         "range_bias": 0.0,                m, added to every measured range
//         "azimuth_bias_deg": 0.0,          added to every measured bearing
//         "elevation_bias_deg": 0.0,        added to every measured elevation (3-D)
//         "site_offset": [0, 0, 0],         m, the true site minus "position" (the surveyed site)
//         "clock_offset": 0.0,              s, a plot's reported time minus its true time
//         "covariance_scale": 1.0,          > 0, reported covariance = scale x the tracker's own
//         "recycle_after": 0.0,             s, >= 0: > 0 reuses a track number this long after its track ends
//         "swap_distance": 0.0 },           m, >= 0: > 0 swaps two local tracks whose targets pass this close
//       "tracker": {                        optional: this sensor's own local tracker
//       (Scenario::sensor_trackers),
//         "filter": "ab",                   as the top-level "tracker"; a key left out is the top-level
//         "process_noise": 5.0 } } ],       "tracker"'s. Absent: the sensor runs the top-level tracker
//     "targets": [ {                        scripted targets; ids unique (default: index)
//       "id": 0, "position": [x, y, z], "velocity": [vx, vy, vz],
//       "segments": [ {                     played in order; the last one lasts to the end
//         "model": "cv",                    "cv" | "ca" | "ct" | "accel_step" | "random_manoeuvre"
//         "duration": 10.0,                 s, >= 0
//         "acceleration": [ax, ay, az],     m/s², "ca" and "accel_step"
//         "turn_rate_deg_s": 3.0,           any sign, "ct" (positive = counter-clockwise)
//         "manoeuvre_period": 1.0,          s, > 0, "random_manoeuvre"
//         "max_turn_rate_deg_s": 0.0,       >= 0, "random_manoeuvre"
//         "max_speed_change": 0.0,          m/s per manoeuvre, >= 0
//         "speed_min": 0.0, "speed_max": 1e9 } ] } ],   m/s, 0 <= speed_min <= speed_max
//     "random_targets": {                   drawn per Monte Carlo run (seed 000 §4)
//       "count": 10,                        integer in [0, 1e7]
//       "area_min": [155000, 155000, 0], "area_max": [205000, 205000, 0],   m, max >= min
//       "speed_min": 100.0, "speed_max": 400.0,                             m/s, 0 <= min <= max
//       "heading_min_deg": 0.0, "heading_max_deg": 360.0,                   min <= max
//       "process_noise": 2.0,               σ of the white-noise acceleration, m/s², >= 0
//       "manoeuvres": {                     optional; present = on (engine/simulation/simulation_truth.hpp)
//         "interval_min": 20, "interval_max": 40,   s, > 0, min <= max: straight legs
//         "duration_min": 5, "duration_max": 15,    s, > 0, min <= max: one manoeuvre
//         "turn_rate_max_deg_s": 3.0,       >= 0; a turn's |rate| is U(max/3, max), random sign
//         "acceleration_max": 10.0,         m/s², >= 0; a step along the velocity is U(-max, max)
//         "p_turn": 0.5 },                  in [0, 1]: probability that a manoeuvre is a turn
//       "group_size": 1,                    integer in [1, 1e6]: formations of this many targets
//       "group_spacing": 0.0 },             m, >= 0: line abreast, neighbours this far apart
//     "tracker": {                          the local tracker of every sensor without its own
//       "filter": "cv",                     "cv" | "ca" | "ab" | "cs" | "cs-nn" | "imm"
//       "process_noise": 2.0 },             m/s², >= 0
//     "recording": {                        optional: a "recorded" track set
//                                           (engine/simulation/simulation_recording.hpp has the rules)
//       "p_seen": 1.0,                      in [0, 1]: P(a sensor ever tracks a target), per pair
//       "coverage_min": 1.0,                in (0, 1]: a local track covers a window of
//       "coverage_max": 1.0,                in (0, 1], >= coverage_min: U(min, max)·duration
//       "false_tracks": 0.0 },              in [0, 100]: per sensor, mean false tracks / targets
//     "wide_area": {                        optional: a radar network over hours
//                                           (engine/simulation/simulation_widearea.hpp has the model)
//       "edge_fraction": 0.12,              in [0, 1): p_detect rolls off over this outer part of a radius
//       "fade_rate": 0.005,                 1/s, >= 0: fades start per (sensor, target) at this rate
//       "fade_duration_min": 20, "fade_duration_max": 120,   s, 0 <= min <= max
//       "masks": [ { "sensor": 0, "target": 3, "start": 100, "end": 160 } ],   scripted fades [start, end)
//       "coast_scans": 3,                   integer in [0, 1000]: missed scans in a row that end a track
//       "birth_rate": 1.5,                  1/s, >= 0: random targets born over the run (Poisson)
//       "lifetime_mean": 3600 }             s, >= 0: random targets live Exp(mean); 0 = the whole run
//   }
// The writer leaves out "manoeuvres" when off, "group_size" / "group_spacing" when 1 / 0,
// "recording" and "wide_area" when they have the defaults, a sensor's "coverage_radius" when it has
// none, its "errors" when they are all zero (scale 1) and its "tracker" when it has none of its
// own, so the text of scenarios without them is unchanged.
#pragma once

#include <string>

#include "kernels/core/scenario.hpp"

namespace trackassoc {

// `source` names the file (or "<string>") in error messages.
Scenario parse_scenario_json(const std::string& text, const std::string& source = "<string>");
Scenario read_scenario_file(const std::string& path);
std::string scenario_to_json(const Scenario& scenario);  // pretty-printed, round-trips exactly

}  // namespace trackassoc
