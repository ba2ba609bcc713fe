#include "kernels/fuzzy/ftaa.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void FtaaOptions::validate() const {
  scales.validate();
  synthesis.validate(3);
  const std::string w = "FtaaOptions.";
  require(std::isfinite(gate) && gate > 0, w + "gate", "expected a gate radius > 0 [m]");
  require(std::isfinite(threshold) && threshold >= 0 && threshold <= 1, w + "threshold",
          "expected a value in [0, 1]");
  require(association_quality >= 1, w + "association_quality", "expected >= 1");
  require(separation_quality >= 1, w + "separation_quality", "expected >= 1");
  require(std::isfinite(track_timeout) && track_timeout >= 0, w + "track_timeout",
          "expected >= 0 [s] (0 = never)");
}

namespace {

struct PairQuality {
  int m = 0;  // consecutive successful decisions
  int d = 0;  // consecutive failures since firm
  bool firm = false;
};

uint64_t pair_key(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

}  // namespace

FtaaResult run_ftaa(const PacketSpans& packets, std::size_t num_sensors, std::size_t num_local,
                    const FtaaOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  validate_packets(packets, num_sensors, num_local);

  // Latest state per local track, and the sensor each local track belongs to.
  std::vector<double> lt(num_local, 0.0), lx(num_local, 0.0), ly(num_local, 0.0), lvx(num_local, 0.0),
      lvy(num_local, 0.0);
  std::vector<uint8_t> has_plot(num_local, 0), has_state(num_local, 0);
  std::vector<int32_t> sensor_of(num_local, -1);
  std::vector<std::vector<int32_t>> tracks_of_sensor(num_sensors);
  std::unordered_map<uint64_t, PairQuality> pairs;
  std::vector<std::vector<int32_t>> firm(num_local);  // adjacency of firm pairs
  auto unlink = [&](int32_t a, int32_t b) {
    std::erase(firm[a], b);
    std::erase(firm[b], a);
  };

  FtaaResult result;
  FusionOutput& out = result.fusion;
  out.resize(packets.size());
  std::vector<double> best_s(num_sensors);
  std::vector<int32_t> best_b(num_sensors);
  std::vector<int32_t> component, stack;
  std::vector<uint8_t> seen(num_local, 0);
  int64_t decisions = 0;
  // The connected component of firm pairs holding `root`, into `component`.
  auto collect_component = [&](int32_t root) {
    component.clear();
    stack.assign(1, root);
    seen[root] = 1;
    while (!stack.empty()) {
      const int32_t c = stack.back();
      stack.pop_back();
      component.push_back(c);
      for (int32_t n : firm[c])
        if (!seen[n]) {
          seen[n] = 1;
          stack.push_back(n);
        }
    }
    for (int32_t c : component) seen[c] = 0;
  };

  for (std::size_t i : arrival_order(packets.t)) {
    const int32_t a = packets.local[i], l = packets.sensor[i];
    const double t = packets.t[i];
    if (sensor_of[a] < 0) {
      sensor_of[a] = l;
      tracks_of_sensor[l].push_back(a);
    }
    if (has_plot[a] && t > lt[a]) {
      const double dt = t - lt[a];
      lvx[a] = (packets.x[i] - lx[a]) / dt;
      lvy[a] = (packets.y[i] - ly[a]) / dt;
      has_state[a] = 1;
    }
    has_plot[a] = 1;
    lt[a] = t;
    lx[a] = packets.x[i];
    ly[a] = packets.y[i];
    if (!has_state[a]) continue;
    ++decisions;

    // This scan's fuzzy decision against every other sensor.
    const PlanarState sa{lx[a], ly[a], lvx[a], lvy[a]};
    std::fill(best_s.begin(), best_s.end(), -1.0);
    std::fill(best_b.begin(), best_b.end(), -1);
    for (std::size_t s = 0; s < num_sensors; ++s) {
      if (static_cast<int32_t>(s) == l) continue;
      for (int32_t b : tracks_of_sensor[s]) {
        if (!has_state[b]) continue;
        const double age = t - lt[b];
        if (options.track_timeout > 0.0 && age > options.track_timeout) continue;
        const PlanarState sb{lx[b] + lvx[b] * age, ly[b] + lvy[b] * age, lvx[b], lvy[b]};
        const FuzzyFactors u = fuzzy_factors(sa, sb);
        if (u.position > options.gate) continue;
        const double S = synthesise(fuzzy_memberships(u, options.scales), options.synthesis);
        if (S > best_s[s]) {
          best_s[s] = S;
          best_b[s] = b;
        }
      }
    }
    // Pair qualities.
    for (std::size_t s = 0; s < num_sensors; ++s) {
      if (static_cast<int32_t>(s) == l) continue;
      const int32_t winner = best_s[s] >= options.threshold ? best_b[s] : -1;
      for (int32_t b : tracks_of_sensor[s]) {
        auto it = pairs.find(pair_key(a, b));
        if (b == winner) {
          PairQuality& q = it == pairs.end() ? pairs[pair_key(a, b)] : it->second;
          ++q.m;
          q.d = 0;
          if (!q.firm && q.m >= options.association_quality) {
            q.firm = true;
            firm[a].push_back(b);
            firm[b].push_back(a);
          }
        } else if (it != pairs.end()) {
          PairQuality& q = it->second;
          if (!q.firm) {
            pairs.erase(it);
          } else if (++q.d >= options.separation_quality) {
            unlink(a, b);
            pairs.erase(it);
          }
        }
      }
    }
    // a's system track: its component of firm pairs; fused state = unweighted mean.
    collect_component(a);
    double fx = 0, fy = 0, fvx = 0, fvy = 0;
    int32_t id = a;
    for (int32_t c : component) {
      id = std::min(id, c);
      const double age = t - lt[c];
      fx += lx[c] + lvx[c] * age;
      fy += ly[c] + lvy[c] * age;
      fvx += lvx[c];
      fvy += lvy[c];
    }
    const double k = static_cast<double>(component.size());
    out.system_track[i] = id;
    out.x[i] = fx / k;
    out.y[i] = fy / k;
    out.vx[i] = fvx / k;
    out.vy[i] = fvy / k;
  }

  // Final components.
  result.final_system_track.assign(num_local, -1);
  int32_t components = 0;
  for (std::size_t a = 0; a < num_local; ++a) {
    if (!has_state[a] || result.final_system_track[a] >= 0) continue;
    ++components;
    collect_component(static_cast<int32_t>(a));
    const int32_t id = *std::min_element(component.begin(), component.end());
    for (int32_t c : component) result.final_system_track[c] = id;
  }
  for (const auto& [key, q] : pairs) result.firm_pairs += q.firm;
  out.num_system_tracks = components;
  out.summary.termination = Termination::kHeuristic;
  out.summary.feasible = true;
  out.summary.iterations = decisions;
  out.summary.wall_time_s = seconds_since(start);
  out.summary.message = std::to_string(decisions) + " decisions, " + std::to_string(result.firm_pairs) +
                        " firm pairs, " + std::to_string(components) + " system tracks";
  return result;
}

}  // namespace trackassoc
