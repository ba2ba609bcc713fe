// The wide-area network model; see engine/simulation/simulation_widearea.hpp.
#include "engine/simulation/simulation_widearea.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "engine/simulation/simulation_errors.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/kalman_converted.hpp"

namespace trackassoc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double exponential(CounterRng& rng, double mean) { return -mean * std::log1p(-rng.uniform()); }

double wrap(double a) {  // to (−π, π], as the clean model's plots
  a = std::remainder(a, 2.0 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

// A conservative horizontal bounding box of a trajectory: its pieces' start points and end point,
// widened by the farthest a piece can move from its start ((|v| + |a|·len)·len).
struct Box {
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  double distance_to(const std::array<double, 3>& p) const {
    const double dx = std::max({x0 - p[0], 0.0, p[0] - x1}), dy = std::max({y0 - p[1], 0.0, p[1] - y1});
    return std::hypot(dx, dy);
  }
};
Box bounding_box(const TargetTrajectory& tr) {
  Box b;
  double margin = 0.0;
  for (const TrajectoryPiece& q : tr.pieces) {
    b.x0 = std::min(b.x0, q.start.p[0]), b.x1 = std::max(b.x1, q.start.p[0]);
    b.y0 = std::min(b.y0, q.start.p[1]), b.y1 = std::max(b.y1, q.start.p[1]);
    const double len = q.t1 - q.t0;
    const double v = std::hypot(q.start.v[0], q.start.v[1]), a = std::hypot(q.start.a[0], q.start.a[1]);
    margin = std::max(margin, (v + a * len) * len);
  }
  b.x0 -= margin, b.y0 -= margin, b.x1 += margin, b.y1 += margin;
  return b;
}

// One emitter seen by the sensor: a target or a phantom, with its streams and state.
struct Emitter {
  const TargetTrajectory* tr = nullptr;
  std::size_t index = 0;  // into the targets, or the phantoms
  bool phantom = false;
  CounterRng detect, fade;
  std::size_t piece = 0;
  double fade_start = kInf, fade_end = 0.0;
  Emitter(const TargetTrajectory* t, std::size_t i, bool p, CounterRng d, CounterRng f)
      : tr(t), index(i), phantom(p), detect(d), fade(f) {}
};

}  // namespace

double coverage_of(const Scenario& sc, std::size_t s) {
  return s < sc.sensor_coverage.size() ? sc.sensor_coverage[s] : 0.0;
}

double coverage_gain(double range, double radius, double f) {
  if (radius <= 0.0) return 1.0;
  if (range > radius) return 0.0;
  const double inner = (1.0 - f) * radius;
  if (range <= inner || f <= 0.0) return 1.0;
  return 0.5 * (1.0 + std::cos(std::numbers::pi * (range - inner) / (f * radius)));
}

void validate_wide_area(const Scenario& sc) {
  const WideAreaSpec& w = sc.wide_area;
  const std::string k = "scenario.wide_area.";
  require(sc.sensor_coverage.empty() || sc.sensor_coverage.size() == sc.sensors.size(),
          "scenario.sensor_coverage",
          "expected none or one radius per sensor (" + std::to_string(sc.sensors.size()) + "), found " +
              std::to_string(sc.sensor_coverage.size()));
  bool any_radius = false;
  for (std::size_t s = 0; s < sc.sensor_coverage.size(); ++s) {
    const double r = sc.sensor_coverage[s];
    const std::string where = "scenario.sensors[" + std::to_string(s) + "].";
    require(std::isfinite(r) && r >= 0.0, where + "coverage_radius",
            "expected a finite radius ≥ 0 [m] (0 = unlimited)");
    any_radius = any_radius || r > 0.0;
    if (sc.is_wide_area() && sc.sensors[s].clutter_rate > 0.0)
      require(r > 0.0, where + "coverage_radius",
              "clutter in a wide-area scenario is spread over the coverage: give this sensor a radius > 0");
  }
  require(std::isfinite(w.edge_fraction) && w.edge_fraction >= 0.0 && w.edge_fraction < 1.0,
          k + "edge_fraction", "expected a fraction in [0, 1) of the coverage radius");
  require(std::isfinite(w.fade_rate) && w.fade_rate >= 0.0, k + "fade_rate", "expected a rate ≥ 0 [1/s]");
  require(std::isfinite(w.fade_duration_min) && w.fade_duration_min >= 0.0, k + "fade_duration_min",
          "expected a duration ≥ 0 [s]");
  require(std::isfinite(w.fade_duration_max) && w.fade_duration_max >= w.fade_duration_min,
          k + "fade_duration_max", "expected a duration ≥ fade_duration_min [s]");
  require(w.fade_rate == 0.0 || w.fade_duration_max > 0.0, k + "fade_duration_max",
          "fade_rate > 0 needs fades of positive length (fade_duration_max > 0)");
  std::set<int32_t> sensor_ids;
  for (const Sensor& x : sc.sensors) sensor_ids.insert(x.id);
  for (std::size_t i = 0; i < w.masks.size(); ++i) {
    const MaskSpec& m = w.masks[i];
    const std::string where = k + "masks[" + std::to_string(i) + "].";
    require(sensor_ids.count(m.sensor) == 1, where + "sensor",
            "expected the id of a sensor of the scenario, found " + std::to_string(m.sensor));
    require(std::isfinite(m.start) && std::isfinite(m.end) && m.end > m.start, where + "end",
            "expected end > start [s]");
  }
  require(w.coast_scans >= 0 && w.coast_scans <= 1000, k + "coast_scans", "expected an integer in [0, 1000]");
  require(w.coast_scans > 0 || (!any_radius && w.fade_rate == 0.0 && w.masks.empty()), k + "coast_scans",
          "coverage radii, fades and masks break tracks only if a track ends when its target is lost: give "
          "coast_scans ≥ 1 (missed scans in a row before a local track is deleted)");
  require(std::isfinite(w.birth_rate) && w.birth_rate >= 0.0 && w.birth_rate * sc.duration <= 1e7,
          k + "birth_rate", "expected a rate ≥ 0 [1/s] with at most 10^7 births over the duration");
  require(std::isfinite(w.lifetime_mean) && w.lifetime_mean >= 0.0, k + "lifetime_mean",
          "expected a mean lifetime ≥ 0 [s] (0 = targets live the whole run)");
  require(w.birth_rate == 0.0 || w.lifetime_mean > 0.0, k + "lifetime_mean",
          "births (birth_rate > 0) need targets that die: give lifetime_mean > 0");
  require(w.birth_rate == 0.0 || sc.random_targets.area_max[0] > sc.random_targets.area_min[0],
          "scenario.random_targets.area_max",
          "born targets start in the random targets' area: give area_min and area_max");
}

double draw_lifetime(const Scenario& sc, uint64_t seed, int run, uint64_t index) {
  if (sc.wide_area.lifetime_mean <= 0.0) return kInf;
  CounterRng rng(seed, static_cast<uint64_t>(run), stream_id(SimulationStream::kLifetime, index));
  return exponential(rng, sc.wide_area.lifetime_mean);
}

std::vector<TargetTrajectory> born_targets(const Scenario& sc, uint64_t seed, int run, int32_t first_id) {
  std::vector<TargetTrajectory> out;
  const WideAreaSpec& w = sc.wide_area;
  if (w.birth_rate <= 0.0) return out;
  RandomTargetSpec spec = sc.random_targets;
  spec.group_size = 1;
  spec.group_spacing = 0.0;
  const int d = spatial_dim(sc.layout);
  const uint64_t r = static_cast<uint64_t>(run);
  CounterRng births(seed, r, stream_id(SimulationStream::kBirth, 0));
  double t = exponential(births, 1.0 / w.birth_rate);
  for (uint64_t b = 0; t <= sc.duration; ++b, t += exponential(births, 1.0 / w.birth_rate)) {
    const uint64_t index = static_cast<uint64_t>(spec.count) + b;
    const double life = draw_lifetime(sc, seed, run, index);
    const double span = std::max(std::min(life, sc.duration - t), sc.truth_step * 1e-6);
    CounterRng rng(seed, r, stream_id(SimulationStream::kRandomTarget, index));
    CounterRng mrng(seed, r, stream_id(SimulationStream::kRandomManoeuvre, index));
    TargetTrajectory tr = random_group_trajectories(spec, first_id + static_cast<int32_t>(b), 1, span,
                                                    sc.truth_step, d, rng, mrng)
                              .front();
    for (TrajectoryPiece& q : tr.pieces) q.t0 += t, q.t1 += t;
    tr.born = t;
    tr.dies = life < sc.duration - t ? t + life : kInf;
    out.push_back(std::move(tr));
  }
  return out;
}

double expected_target_seconds(const Scenario& sc) {
  const double T = sc.duration, L = sc.wide_area.lifetime_mean, lambda = sc.wide_area.birth_rate;
  const double n0 = static_cast<double>(sc.targets.size() + sc.random_targets.count);
  if (L <= 0.0) return n0 * T;
  const double lived = L * (1.0 - std::exp(-T / L));  // E[min(life, T)]
  return static_cast<double>(sc.targets.size()) * T + sc.random_targets.count * lived +
         lambda * L * (T - lived);
}

double coverage_share(const Scenario& sc, std::size_t s) {
  const double R = coverage_of(sc, s);
  const RandomTargetSpec& rt = sc.random_targets;
  const double area = (rt.area_max[0] - rt.area_min[0]) * (rt.area_max[1] - rt.area_min[1]);
  if (R <= 0.0 || area <= 0.0) return 1.0;
  return std::min(1.0, std::numbers::pi * R * R / area);
}

SensorMeasurements simulate_sensor_wide(const Scenario& sc, std::size_t s,
                                        const std::vector<TargetTrajectory>& targets, uint64_t seed, int run,
                                        const SensorRecording* recording) {
  const Sensor& sensor = sc.sensors[s];
  const SensorErrors& errors = sensor_errors_of(sc, s);
  const Sensor site = true_site(sensor, errors);
  const WideAreaSpec& w = sc.wide_area;
  const double R = coverage_of(sc, s);
  const int d = spatial_dim(sc.layout);
  const uint64_t r = static_cast<uint64_t>(run);
  SensorMeasurements out;
  for (long k = 0;; ++k) {
    const double t = sensor.offset + static_cast<double>(k) * sensor.period;
    if (t > sc.duration + 1e-9) break;
    out.scans.push_back(t);
  }
  // The emitters that can come within R at some time of their life.
  std::vector<Emitter> em;
  auto add = [&](const TargetTrajectory& tr, std::size_t i, bool phantom) {
    if (R > 0.0 && bounding_box(tr).distance_to(site.position) > R) return;
    const uint64_t fade_index = phantom ? targets.size() + i : i;
    em.emplace_back(
        &tr, i, phantom,
        CounterRng(seed, r,
                   stream_id(phantom ? SimulationStream::kPhantomDetection : SimulationStream::kDetection, s),
                   i),
        CounterRng(seed, r, stream_id(SimulationStream::kFade, s), fade_index));
    em.back().fade_end = tr.born;
  };
  for (std::size_t j = 0; j < targets.size(); ++j) add(targets[j], j, false);
  if (recording)
    for (std::size_t k = 0; k < recording->phantoms.size(); ++k) add(recording->phantoms[k], k, true);
  std::vector<MaskSpec> masks;
  for (const MaskSpec& m : w.masks)
    if (m.sensor == sensor.id) masks.push_back(m);
  CounterRng clutter_rng(seed, r, stream_id(SimulationStream::kClutter, s));
  Measurements& m = out.m;
  auto push = [&](double t, double range, double bearing, double elevation, int32_t target) {
    m.sensor.push_back(sensor.id);
    m.t.push_back(t);
    m.range.push_back(range);
    m.bearing.push_back(bearing);
    if (d == 3) m.elevation.push_back(elevation);
    m.target.push_back(target);
  };
  for (double t : out.scans) {
    for (Emitter& e : em) {
      const TargetTrajectory& tr = *e.tr;
      if (!tr.alive(t)) continue;
      if (recording &&
          !(e.phantom ? recording->keeps_phantom(e.index, t) : recording->keeps_target(e.index, t)))
        continue;
      const std::array<double, 3> p = tr.position_at(t - errors.clock_offset, e.piece);
      PolarPoint q = cartesian_to_polar(d, site, p);
      if (R > 0.0 && q.range > R) continue;
      if (w.fade_rate > 0.0)
        while (t >= e.fade_end) {
          e.fade_start = e.fade_end + exponential(e.fade, 1.0 / w.fade_rate);
          e.fade_end = e.fade_start + e.fade.uniform(w.fade_duration_min, w.fade_duration_max);
        }
      if (t >= e.fade_start && t < e.fade_end) continue;
      const bool masked = !e.phantom && std::any_of(masks.begin(), masks.end(), [&](const MaskSpec& k) {
        return k.target == tr.id && t >= k.start && t < k.end;
      });
      if (masked) continue;
      const bool hit = e.detect.uniform() < sensor.p_detect * coverage_gain(q.range, R, w.edge_fraction);
      const double nr = e.detect.normal(), nb = e.detect.normal(), ne = d == 3 ? e.detect.normal() : 0.0;
      if (!hit) continue;
      q.range += errors.range_bias;
      q.bearing += errors.azimuth_bias;
      q.elevation += errors.elevation_bias;
      push(t, std::max(0.0, q.range + sensor.sigma_range * nr), wrap(q.bearing + sensor.sigma_bearing * nb),
           std::clamp(q.elevation + sensor.sigma_elevation * ne, -std::numbers::pi / 2, std::numbers::pi / 2),
           tr.id);
    }
    const int false_plots = poisson_draw(clutter_rng, sensor.clutter_rate);
    for (int c = 0; c < false_plots; ++c) {
      const double range = clutter_rng.uniform(0.0, R);
      const double bearing = wrap(clutter_rng.uniform(-std::numbers::pi, std::numbers::pi));
      push(t, range, bearing, d == 3 ? clutter_rng.uniform(0.0, 10.0 * std::numbers::pi / 180.0) : 0.0, -1);
    }
  }
  return out;
}

}  // namespace trackassoc
