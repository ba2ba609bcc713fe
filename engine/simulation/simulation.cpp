// Scenario simulation (docs/design.md §4.1); see engine/simulation/simulation.hpp,
// engine/simulation/simulation_truth.hpp (trajectories) and engine/simulation/simulation_tracker.hpp (local
// tracking).
//
// Measurement model, per sensor scan t_k = offset + k·period ≤ duration and per target:
//   detected with probability p_detect; then range, bearing (and elevation in 3-D) of the true
//   position plus N(0, σ²) errors, bearing wrapped to (−π, π] (conventions in kalman_converted.hpp).
// Clutter: Poisson(clutter_rate) false plots per scan (target = −1), uniform in the sensor's
// coverage, taken as the polar box range ∈ [0, 1.2·r_max], bearing ∈ [−π, π), elevation ∈
// [φ_min − 0.05, φ_max + 0.05] rad, where r_max and φ_min/φ_max are the extremes over the true
// targets seen by that sensor during the run (the scenario has no explicit coverage field).
// Random streams: one CounterRng per (sensor, target) for detections and noise, one per sensor for
// clutter, one per target for manoeuvres and random targets (one per group in formations) — all
// keyed (seed, run, stream id), so the output is bit-identical for any thread count.
// Recording model (Scenario::recording): engine/simulation/simulation_recording.hpp; phantoms are measured in
// each scan after the true targets and before the clutter, from their own streams.
// Size guard: the memory a run needs at least (check_size) is checked against the memory budget
// (io/memory_budget.hpp, --memory-budget) before anything is allocated.
#include "engine/simulation/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "engine/simulation/simulation_errors.hpp"
#include "engine/simulation/simulation_recording.hpp"
#include "engine/simulation/simulation_tracker.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "engine/simulation/simulation_widearea.hpp"
#include "io/memory_budget.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/kalman_converted.hpp"

namespace trackassoc {

namespace {

void validate_recording(const Scenario& sc) {
  const RecordingSpec& g = sc.recording;
  require(g.p_seen >= 0.0 && g.p_seen <= 1.0, "scenario.recording.p_seen",
          "expected a probability in [0, 1]");
  require(g.coverage_min > 0.0 && g.coverage_min <= 1.0, "scenario.recording.coverage_min",
          "expected a fraction in (0, 1]");
  require(g.coverage_max >= g.coverage_min && g.coverage_max <= 1.0, "scenario.recording.coverage_max",
          "expected a fraction in [coverage_min, 1]");
  require(std::isfinite(g.false_tracks) && g.false_tracks >= 0.0 && g.false_tracks <= 100.0,
          "scenario.recording.false_tracks", "expected a fraction of the targets in [0, 100]");
  const RandomTargetSpec& rt = sc.random_targets;
  require(rt.group_size >= 1, "scenario.random_targets.group_size", "expected an integer ≥ 1");
  require(std::isfinite(rt.group_spacing) && rt.group_spacing >= 0.0, "scenario.random_targets.group_spacing",
          "expected a finite spacing ≥ 0 [m]");
  const ManoeuvreSpec& m = rt.manoeuvres;
  if (!m.enabled) return;
  const std::string w = "scenario.random_targets.manoeuvres.";
  require(std::isfinite(m.interval_min) && m.interval_min > 0.0, w + "interval_min", "expected > 0 [s]");
  require(std::isfinite(m.interval_max) && m.interval_max >= m.interval_min, w + "interval_max",
          "expected ≥ interval_min [s]");
  require(std::isfinite(m.duration_min) && m.duration_min > 0.0, w + "duration_min", "expected > 0 [s]");
  require(std::isfinite(m.duration_max) && m.duration_max >= m.duration_min, w + "duration_max",
          "expected ≥ duration_min [s]");
  require(std::isfinite(m.turn_rate_max) && m.turn_rate_max >= 0.0, w + "turn_rate_max", "expected ≥ 0");
  require(std::isfinite(m.acceleration_max) && m.acceleration_max >= 0.0, w + "acceleration_max",
          "expected ≥ 0 [m/s²]");
  require(m.p_turn >= 0.0 && m.p_turn <= 1.0, w + "p_turn", "expected a probability in [0, 1]");
}

// A sensor's own tracker (Scenario::sensor_trackers) is checked as the scenario's is, by building
// its filter bank; the message names the sensor.
void validate_sensor_trackers(const Scenario& sc) {
  if (sc.sensor_trackers.empty()) return;
  require(sc.sensor_trackers.size() == sc.sensors.size(), "scenario.sensor_trackers",
          "expected none or one per sensor (" + std::to_string(sc.sensors.size()) + "), found " +
              std::to_string(sc.sensor_trackers.size()));
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    if (!sc.sensor_trackers[s]) continue;
    try {
      make_local_filter_bank(*sc.sensor_trackers[s], spatial_dim(sc.layout), 0);
    } catch (const InputError& e) {  // "tracker.filter: ..." -> "scenario.sensors[s].tracker.filter: ..."
      throw InputError("scenario.sensors[" + std::to_string(s) + "]." + e.what());
    }
  }
}

// Refuses a scenario whose run would not fit the memory budget, before anything is allocated.
// What a run holds at least, before the writer copies it: truth rows (id, t, state) for every
// target and truth step; per sensor and scan, the plots of the targets and of the expected false
// tracks (detected with p_detect) and the clutter, each with the local track report it updates
// (id, number, t, state, full covariance).
void check_size(const Scenario& sc) {
  double targets = static_cast<double>(sc.targets.size()) + static_cast<double>(sc.random_targets.count);
  const double d = spatial_dim(sc.layout), D = 2.0 * d;
  const double steps = std::floor(sc.duration / sc.truth_step + 1e-9) + 1.0;
  double bytes = targets * steps * (12.0 + 8.0 * D);
  // Wide area (engine/simulation/simulation_widearea.hpp): targets exist only over their lives and
  // a sensor sees them only within its coverage, so truth rows and plots follow the expected
  // target-seconds of existence (× the sensor's share of the area) instead of targets × duration.
  const double lived = sc.is_wide_area() ? expected_target_seconds(sc) : 0.0;
  if (sc.is_wide_area()) {
    targets += sc.wide_area.birth_rate * sc.duration;
    bytes = (lived / sc.truth_step + targets) * (12.0 + 8.0 * D) + targets * 1e3;  // + trajectory pieces
  }
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    const Sensor& x = sc.sensors[s];
    const double scans = std::floor((sc.duration - x.offset) / x.period + 1e-9) + 1.0;
    const double seen = sc.is_wide_area() ? lived * coverage_share(sc, s) / x.period : scans * targets;
    const double plots = seen * (1.0 + sc.recording.false_tracks) * x.p_detect + scans * x.clutter_rate;
    // Wide area: the sensors' local tracks and their merged table are held together once (measured
    // peak of `widearea`: 2.3 GB against this estimate's 3.8 GiB), so a track row counts twice.
    bytes += plots * ((24.0 + 8.0 * d) + (sc.is_wide_area() ? 2.0 : 1.0) * (16.0 + 8.0 * (D + D * D)));
  }
  char what[240];
  std::snprintf(what, sizeof what,
                "scenario '%.80s' (%.4g targets × %.4g s, truth every %g s, %zu sensors; see %s, duration)",
                sc.name.c_str(), targets, sc.duration, sc.truth_step, sc.sensors.size(),
                sc.random_targets.count > 0 ? "scenario.random_targets.count" : "scenario.targets");
  require_memory(bytes_of(bytes, 1), what);
}

void validate_scenario(const Scenario& sc) {
  require(std::isfinite(sc.duration) && sc.duration > 0.0, "scenario.duration",
          "expected a finite duration > 0 [s]");
  require(std::isfinite(sc.truth_step) && sc.truth_step > 0.0, "scenario.truth_step",
          "expected a finite step > 0 [s]");
  require(sc.duration / sc.truth_step <= 1e7, "scenario.truth_step",
          "more than 10^7 truth samples; increase the step");
  require(sc.random_targets.count >= 0, "scenario.random_targets.count", "expected ≥ 0");
  require(sc.random_targets.process_noise >= 0.0, "scenario.random_targets.process_noise", "expected σ ≥ 0");
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    const Sensor& x = sc.sensors[s];
    const std::string w = "scenario.sensors[" + std::to_string(s) + "].";
    require(std::isfinite(x.period) && x.period > 0.0, w + "period", "expected a scan period > 0 [s]");
    require(sc.duration / x.period <= 1e7, w + "period", "more than 10^7 scans; increase the period");
    require(std::isfinite(x.offset) && x.offset >= 0.0, w + "offset", "expected an offset ≥ 0 [s]");
    require(x.p_detect >= 0.0 && x.p_detect <= 1.0, w + "p_detect", "expected a probability in [0, 1]");
    require(std::isfinite(x.clutter_rate) && x.clutter_rate >= 0.0 && x.clutter_rate <= 1e5,
            w + "clutter_rate", "expected a rate in [0, 1e5] per scan");
    require(x.sigma_range >= 0.0 && x.sigma_bearing >= 0.0 && x.sigma_elevation >= 0.0, w + "sigma",
            "expected standard deviations ≥ 0");
  }
  validate_recording(sc);
  validate_sensor_errors(sc);
  validate_sensor_trackers(sc);
  validate_wide_area(sc);
  check_size(sc);
}

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

}  // namespace

SensorMeasurements simulate_sensor(const Scenario& sc, std::size_t s,
                                   const std::vector<TargetTrajectory>& targets, uint64_t seed, int run,
                                   const SensorRecording* recording) {
  if (sc.is_wide_area()) return simulate_sensor_wide(sc, s, targets, seed, run, recording);
  const Sensor& sensor = sc.sensors[s];
  const SensorErrors& errors = sensor_errors_of(sc, s);
  const Sensor site = true_site(sensor, errors);  // where the sensor really is
  const int d = spatial_dim(sc.layout);
  SensorMeasurements out;
  for (long k = 0;; ++k) {
    const double t = sensor.offset + static_cast<double>(k) * sensor.period;
    if (t > sc.duration + 1e-9) break;
    out.scans.push_back(t);
  }
  // Coverage of the clutter: extremes of the true polar coordinates over the run.
  double r_max = 0.0, el_min = 0.0, el_max = 0.0;
  bool first = true;
  std::vector<CounterRng> rng;
  rng.reserve(targets.size());
  for (std::size_t j = 0; j < targets.size(); ++j)
    rng.emplace_back(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kDetection, s), j);
  CounterRng clutter_rng(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kClutter, s));
  const std::size_t phantoms = recording ? recording->phantoms.size() : 0;
  std::vector<CounterRng> phantom_rng;
  phantom_rng.reserve(phantoms);
  for (std::size_t k = 0; k < phantoms; ++k)
    phantom_rng.emplace_back(seed, static_cast<uint64_t>(run),
                             stream_id(SimulationStream::kPhantomDetection, s), k);
  Measurements& m = out.m;
  // Pass 1 finds the coverage; pass 2 draws. Both passes are cheap next to the filtering.
  for (double t : out.scans)
    for (const auto& tr : targets) {
      const PolarPoint q = cartesian_to_polar(d, sensor, tr.at(t).p);
      r_max = std::max(r_max, q.range);
      el_min = first ? q.elevation : std::min(el_min, q.elevation);
      el_max = first ? q.elevation : std::max(el_max, q.elevation);
      first = false;
    }
  const double el_lo = std::max(-std::numbers::pi / 2, el_min - 0.05),
               el_hi = std::min(std::numbers::pi / 2, el_max + 0.05);
  // One plot of `tr` at t with the draws of `r`, kept when detected and `keep`.
  // Registration errors (engine/simulation/simulation_errors.hpp): the plot reported at t is of the
  // true position at t − clock_offset, from the true site, plus the biases.
  auto measure = [&](const TargetTrajectory& tr, CounterRng& r, double t, bool keep) {
    const bool hit = r.uniform() < sensor.p_detect;
    PolarPoint q = errors.is_default() ? cartesian_to_polar(d, sensor, tr.at(t).p)
                                       : cartesian_to_polar(d, site, tr.at(t - errors.clock_offset).p);
    if (!errors.is_default()) {
      q.range += errors.range_bias;
      q.bearing += errors.azimuth_bias;
      q.elevation += errors.elevation_bias;
    }
    const double nr = r.normal(), nb = r.normal(), ne = d == 3 ? r.normal() : 0.0;
    if (!hit || !keep) return;
    m.sensor.push_back(sensor.id);
    m.t.push_back(t);
    m.range.push_back(std::max(0.0, q.range + sensor.sigma_range * nr));
    m.bearing.push_back(wrap_angle(q.bearing + sensor.sigma_bearing * nb));
    if (d == 3)
      m.elevation.push_back(
          std::clamp(q.elevation + sensor.sigma_elevation * ne, -std::numbers::pi / 2, std::numbers::pi / 2));
    m.target.push_back(tr.id);
  };
  for (double t : out.scans) {
    for (std::size_t j = 0; j < targets.size(); ++j)
      measure(targets[j], rng[j], t, !recording || recording->keeps_target(j, t));
    for (std::size_t k = 0; k < phantoms; ++k)
      measure(recording->phantoms[k], phantom_rng[k], t, recording->keeps_phantom(k, t));
    const int false_plots = poisson_draw(clutter_rng, sensor.clutter_rate);
    for (int c = 0; c < false_plots; ++c) {
      m.sensor.push_back(sensor.id);
      m.t.push_back(t);
      m.range.push_back(clutter_rng.uniform(0.0, 1.2 * r_max));
      m.bearing.push_back(wrap_angle(clutter_rng.uniform(-std::numbers::pi, std::numbers::pi)));
      if (d == 3) m.elevation.push_back(clutter_rng.uniform(el_lo, el_hi));
      m.target.push_back(-1);
    }
  }
  return out;
}

std::vector<TargetTrajectory> simulate_trajectories(const Scenario& sc, uint64_t seed, int run) {
  validate_scenario(sc);
  const int d = spatial_dim(sc.layout);
  std::vector<TargetTrajectory> targets;
  int32_t next_id = 0;
  for (std::size_t i = 0; i < sc.targets.size(); ++i) {
    CounterRng rng(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kTargetManoeuvre, i));
    targets.push_back(scripted_trajectory(sc.targets[i], sc.duration, d, rng));
    next_id = std::max(next_id, sc.targets[i].id + 1);
  }
  const RandomTargetSpec& rt = sc.random_targets;
  // Turnover (engine/simulation/simulation_widearea.hpp): a random target (group) of life L < duration
  // is drawn only over [0, L] (the same draws as the first pieces of a full-length one).
  auto life_span = [&](TargetTrajectory& tr, double life) {
    if (life < sc.duration) tr.dies = life;
  };
  if (rt.group_size == 1 && !rt.manoeuvres.enabled) {
    for (int32_t k = 0; k < rt.count; ++k) {
      CounterRng rng(seed, static_cast<uint64_t>(run),
                     stream_id(SimulationStream::kRandomTarget, static_cast<uint64_t>(k)));
      const double life = draw_lifetime(sc, seed, run, static_cast<uint64_t>(k));
      targets.push_back(
          random_trajectory(rt, next_id + k, std::min(sc.duration, life), sc.truth_step, d, rng));
      life_span(targets.back(), life);
    }
  } else {
    // Groups (formations; a group of one with manoeuvres): group g draws from the streams of
    // random target g.
    for (int32_t first = 0, g = 0; first < rt.count; first += rt.group_size, ++g) {
      const int members = std::min(rt.group_size, rt.count - first);
      CounterRng rng(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kRandomTarget, g));
      CounterRng mrng(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kRandomManoeuvre, g));
      const double life = draw_lifetime(sc, seed, run, static_cast<uint64_t>(g));
      for (auto& tr : random_group_trajectories(rt, next_id + first, members, std::min(sc.duration, life),
                                                sc.truth_step, d, rng, mrng)) {
        targets.push_back(std::move(tr));
        life_span(targets.back(), life);
      }
    }
  }
  for (auto& tr : born_targets(sc, seed, run, next_id + rt.count)) targets.push_back(std::move(tr));
  return targets;
}

namespace {

// The local tracks of a valid scenario can still be degenerate when a target passes over a sensor:
// the measured range is clamped at 0 and the bearing is undefined, so the converted-measurement
// covariance (Lerro & Bar-Shalom 1993, Eq. 4) is singular, and so are the tracks it updates. Such
// tracks would fail when written (as "/tracks/cov: not positive definite" of the engine's own
// output); this says what in the scenario causes it, with the targets' closest approach.
void explain_degenerate_tracks(const Scenario& sc, const std::vector<TargetTrajectory>& targets,
                               const TrackTable& tracks, uint64_t seed, int run) {
  try {
    track_validation::check_tracks("simulated local tracks", tracks, sc.sensors);
  } catch (const InputError& e) {
    const int d = spatial_dim(sc.layout);
    double closest = std::numeric_limits<double>::infinity(), when = 0.0;
    int32_t target = -1, sensor = -1;
    const long steps = static_cast<long>(std::floor(sc.duration / sc.truth_step + 1e-9));
    for (const Sensor& s : sc.sensors)
      for (const auto& tr : targets)
        for (long k = 0; k <= steps; ++k) {
          const double t = static_cast<double>(k) * sc.truth_step;
          const double r = cartesian_to_polar(d, s, tr.at(t).p).range;
          if (r < closest) closest = r, when = t, target = tr.id, sensor = s.id;
        }
    std::string why = e.what();
    if (target >= 0)
      why += "; target " + std::to_string(target) + " comes within " + std::to_string(closest) +
             " m of sensor " + std::to_string(sensor) + " at t = " + std::to_string(when) +
             " s, where a radar's range-bearing measurement is degenerate: keep the targets (targets, "
             "random_targets.area_min/area_max) away from the sensor positions";
    throw InputError("scenario '" + sc.name + "' (seed " + std::to_string(seed) + ", run " +
                     std::to_string(run) + "): its simulated tracks are degenerate: " + why);
  }
}

}  // namespace

SimulationResult simulate(const Scenario& sc, uint64_t seed, int run) {
  require(run >= 0, "simulate.run", "expected a run number ≥ 0");
  const std::vector<TargetTrajectory> targets = simulate_trajectories(sc, seed, run);
  const int d = spatial_dim(sc.layout);
  SimulationResult result{TruthTable(sc.layout), Measurements{}, TrackTable(sc.layout)};
  const long steps = static_cast<long>(std::floor(sc.duration / sc.truth_step + 1e-9));
  for (const auto& tr : targets)
    for (long k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) * sc.truth_step;
      if (!tr.alive(t)) continue;
      const Kinematics q = tr.at(t);
      result.truth.target.push_back(tr.id);
      result.truth.t.push_back(t);
      for (int a = 0; a < d; ++a) {
        result.truth.state[a].push_back(q.p[a]);
        result.truth.state[d + a].push_back(q.v[a]);
      }
    }
  const RecordingPlan plan = plan_recording(sc, targets, seed, run);
  std::vector<SensorMeasurements> per_sensor(sc.sensors.size());
  parallel_for_range(sc.sensors.size(), 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t s = b; s < e; ++s)
      per_sensor[s] = simulate_sensor(sc, s, targets, seed, run, plan.active ? &plan.sensors[s] : nullptr);
  });
  Measurements& all = result.measurements;
  std::vector<std::vector<double>> scans;
  for (auto& p : per_sensor) {
    all.sensor.insert(all.sensor.end(), p.m.sensor.begin(), p.m.sensor.end());
    all.t.insert(all.t.end(), p.m.t.begin(), p.m.t.end());
    all.range.insert(all.range.end(), p.m.range.begin(), p.m.range.end());
    all.bearing.insert(all.bearing.end(), p.m.bearing.begin(), p.m.bearing.end());
    all.elevation.insert(all.elevation.end(), p.m.elevation.begin(), p.m.elevation.end());
    all.target.insert(all.target.end(), p.m.target.begin(), p.m.target.end());
    scans.push_back(std::move(p.scans));
  }
  std::vector<LocalTrackerSpec> trackers;
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) trackers.push_back(tracker_of(sc, s));
  std::vector<TrackLifecycle> lifecycle;
  if (sc.is_wide_area())
    for (std::size_t s = 0; s < sc.sensors.size(); ++s)
      lifecycle.push_back({sc.wide_area.coast_scans, coverage_of(sc, s)});
  result.tracks =
      track_measurements(all, sc.sensors, sc.layout, trackers, seed, run, scans, lifecycle).tracks;
  if (sc.is_wide_area() && !plan.active) drop_short_tracks(result.tracks);
  apply_recording(plan, sc, targets, result);
  apply_sensor_errors(sc, targets, result.tracks);
  explain_degenerate_tracks(sc, targets, result.tracks, seed, run);
  return result;
}

}  // namespace trackassoc
