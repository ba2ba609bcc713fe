// The sensor error model of the simulation; see engine/simulation/simulation_errors.hpp.
#include "engine/simulation/simulation_errors.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>

#include "kernels/core/error.hpp"

namespace trackassoc {

namespace {

using Key = std::pair<int32_t, int32_t>;  // (sensor id, track number)

// Rows of each local track of sensor `id`, in time order.
std::map<int32_t, std::vector<std::size_t>> rows_by_track(const TrackTable& t, int32_t id) {
  std::map<int32_t, std::vector<std::size_t>> rows;
  for (std::size_t r = 0; r < t.size(); ++r)
    if (t.sensor[r] == id) rows[t.track[r]].push_back(r);
  for (auto& [trk, v] : rows)
    std::stable_sort(v.begin(), v.end(), [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; });
  return rows;
}

void scale_covariances(TrackTable& t, int32_t id, double scale) {
  for (std::size_t r = 0; r < t.size(); ++r)
    if (t.sensor[r] == id)
      for (auto& c : t.cov) c[r] *= scale;
}

// Swaps at the closest approach of two tracks' targets (see the header).
void swap_at_crossings(TrackTable& t, int32_t id, double distance, int d,
                       const std::unordered_map<int32_t, const TargetTrajectory*>& trajectory) {
  const auto rows = rows_by_track(t, id);
  struct Crossing {
    double tc;
    int32_t a, b;
  };
  std::vector<Crossing> crossings;
  for (auto ia = rows.begin(); ia != rows.end(); ++ia)
    for (auto ib = std::next(ia); ib != rows.end(); ++ib) {
      const int32_t ta = t.truth[ia->second.front()], tb = t.truth[ib->second.front()];
      if (ta < 0 || tb < 0 || ta == tb) continue;
      const TargetTrajectory &A = *trajectory.at(ta), &B = *trajectory.at(tb);
      // Closest approach over the times both tracks report (one sensor: the same scan times).
      std::map<double, std::size_t> times_b;
      for (std::size_t r : ib->second) times_b[t.t[r]] = r;
      double best = distance, tc = 0.0;
      bool found = false;
      for (std::size_t r : ia->second) {
        if (!times_b.count(t.t[r])) continue;
        const Kinematics ka = A.at(t.t[r]), kb = B.at(t.t[r]);
        double sq = 0.0;
        for (int i = 0; i < d; ++i) sq += (ka.p[i] - kb.p[i]) * (ka.p[i] - kb.p[i]);
        if (std::sqrt(sq) < best) best = std::sqrt(sq), tc = t.t[r], found = true;
      }
      if (!found) continue;
      auto margin_ok = [&](const std::vector<std::size_t>& v) {
        const auto before = std::count_if(v.begin(), v.end(), [&](std::size_t r) { return t.t[r] < tc; });
        const auto after = std::count_if(v.begin(), v.end(), [&](std::size_t r) { return t.t[r] > tc; });
        return before >= kSwapMargin && after >= kSwapMargin;
      };
      if (margin_ok(ia->second) && margin_ok(ib->second)) crossings.push_back({tc, ia->first, ib->first});
    }
  std::stable_sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) {
    return std::tie(x.tc, x.a, x.b) < std::tie(y.tc, y.a, y.b);
  });
  std::map<int32_t, bool> swapped;
  for (const Crossing& c : crossings) {
    if (swapped[c.a] || swapped[c.b]) continue;
    swapped[c.a] = swapped[c.b] = true;
    for (std::size_t r : rows.at(c.a))
      if (t.t[r] > c.tc) t.track[r] = c.b;
    for (std::size_t r : rows.at(c.b))
      if (t.t[r] > c.tc) t.track[r] = c.a;
  }
}

// Numbers given anew in order of first report, reusing one recycle_after after its track ended.
void recycle_numbers(TrackTable& t, int32_t id, double recycle_after) {
  const auto rows = rows_by_track(t, id);
  std::vector<std::tuple<double, double, int32_t>> tracks;  // (first t, last t, old number)
  for (const auto& [trk, v] : rows) tracks.emplace_back(t.t[v.front()], t.t[v.back()], trk);
  std::sort(tracks.begin(), tracks.end());
  std::vector<double> free_from;  // per new number: when it may be reused
  std::map<int32_t, int32_t> renumber;
  for (const auto& [first, last, old] : tracks) {
    int32_t number = -1;
    for (std::size_t k = 0; k < free_from.size() && number < 0; ++k)
      if (free_from[k] <= first) number = static_cast<int32_t>(k);
    if (number < 0) {
      number = static_cast<int32_t>(free_from.size());
      free_from.push_back(0.0);
    }
    free_from[number] = last + recycle_after;
    renumber[old] = number;
  }
  for (const auto& [trk, v] : rows)
    for (std::size_t r : v) t.track[r] = renumber.at(trk);
}

}  // namespace

const SensorErrors& sensor_errors_of(const Scenario& sc, std::size_t s) {
  static const SensorErrors none;
  return s < sc.sensor_errors.size() ? sc.sensor_errors[s] : none;
}

void validate_sensor_errors(const Scenario& sc) {
  if (sc.sensor_errors.empty()) return;
  require(sc.sensor_errors.size() == sc.sensors.size(), "scenario.sensor_errors",
          "expected one entry per sensor (" + std::to_string(sc.sensors.size()) + "), found " +
              std::to_string(sc.sensor_errors.size()));
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    const SensorErrors& e = sc.sensor_errors[s];
    const std::string w = "scenario.sensors[" + std::to_string(s) + "].errors.";
    // Bounds well beyond any sensor, so that no error can overflow the geometry.
    require(std::isfinite(e.range_bias) && std::abs(e.range_bias) <= 1e6, w + "range_bias",
            "expected a bias within ±10^6 m");
    require(std::isfinite(e.azimuth_bias) && std::abs(e.azimuth_bias) < 0.5, w + "azimuth_bias",
            "expected a finite bias below 0.5 rad");
    require(std::isfinite(e.elevation_bias) && std::abs(e.elevation_bias) < 0.5, w + "elevation_bias",
            "expected a finite bias below 0.5 rad");
    for (double v : e.site_offset)
      require(std::isfinite(v) && std::abs(v) <= 1e7, w + "site_offset",
              "expected coordinates within ±10^7 m");
    require(std::isfinite(e.clock_offset) && std::abs(e.clock_offset) <= sc.duration, w + "clock_offset",
            "expected an offset within ± the duration [s]");
    require(std::isfinite(e.covariance_scale) && e.covariance_scale > 0.0 && e.covariance_scale <= 1e6,
            w + "covariance_scale", "expected a factor in (0, 10^6]");
    require(std::isfinite(e.recycle_after) && e.recycle_after >= 0.0, w + "recycle_after",
            "expected a finite time >= 0 [s]");
    require(std::isfinite(e.swap_distance) && e.swap_distance >= 0.0 && e.swap_distance <= 1e7,
            w + "swap_distance", "expected a distance in [0, 10^7] m");
  }
}

Sensor true_site(const Sensor& surveyed, const SensorErrors& e) {
  Sensor s = surveyed;
  for (int i = 0; i < 3; ++i) s.position[i] += e.site_offset[i];
  return s;
}

void apply_sensor_errors(const Scenario& sc, const std::vector<TargetTrajectory>& targets,
                         TrackTable& tracks) {
  if (sc.sensor_errors.empty()) return;
  std::unordered_map<int32_t, const TargetTrajectory*> trajectory;
  for (const auto& tr : targets) trajectory[tr.id] = &tr;
  const int d = spatial_dim(sc.layout);
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    const SensorErrors& e = sc.sensor_errors[s];
    const int32_t id = sc.sensors[s].id;
    if (e.covariance_scale != 1.0) scale_covariances(tracks, id, e.covariance_scale);
    if (e.swap_distance > 0.0) swap_at_crossings(tracks, id, e.swap_distance, d, trajectory);
    if (e.recycle_after > 0.0) recycle_numbers(tracks, id, e.recycle_after);
  }
}

}  // namespace trackassoc
