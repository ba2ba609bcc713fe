// The recording model of the simulation; see engine/simulation/simulation_recording.hpp.
#include "engine/simulation/simulation_recording.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

namespace trackassoc {

namespace {

// A coverage window of one (sensor, target): three draws, whatever the outcome.
void draw_window(const RecordingSpec& g, double duration, double period, CounterRng& rng, double& start,
                 double& end) {
  const double f = rng.uniform(g.coverage_min, g.coverage_max);
  const double length = std::min(duration, std::max(f * duration, kMinWindowScans * period));
  start = rng.uniform(0.0, duration - length);
  end = start + length;
}

// How phantoms move: the random targets' spec, or the scripted targets' box and speeds.
RandomTargetSpec phantom_spec(const Scenario& sc, const std::vector<TargetTrajectory>& targets) {
  RandomTargetSpec spec;
  if (sc.random_targets.count > 0) {
    spec = sc.random_targets;
    spec.group_size = 1;
    spec.group_spacing = 0.0;
    return spec;
  }
  bool first = true;
  for (const auto& tr : targets) {
    const Kinematics k = tr.at(0.0);
    const double speed = std::sqrt(k.v[0] * k.v[0] + k.v[1] * k.v[1] + k.v[2] * k.v[2]);
    for (int i = 0; i < 3; ++i) {
      spec.area_min[i] = first ? k.p[i] : std::min(spec.area_min[i], k.p[i]);
      spec.area_max[i] = first ? k.p[i] : std::max(spec.area_max[i], k.p[i]);
    }
    spec.speed_min = first ? speed : std::min(spec.speed_min, speed);
    spec.speed_max = first ? speed : std::max(spec.speed_max, speed);
    first = false;
  }
  spec.heading_min = 0.0;
  spec.heading_max = 2.0 * std::numbers::pi;
  spec.process_noise = 0.0;
  return spec;
}

}  // namespace

void keep_track_rows(TrackTable& t, const std::vector<uint8_t>& keep) {
  auto compact = [&](auto& column) {
    std::size_t w = 0;
    for (std::size_t r = 0; r < keep.size(); ++r)
      if (keep[r]) column[w++] = column[r];
    column.resize(w);
  };
  compact(t.sensor);
  compact(t.track);
  compact(t.t);
  compact(t.truth);
  for (auto& c : t.state) compact(c);
  for (auto& c : t.cov) compact(c);
}

void drop_short_tracks(TrackTable& tracks) {
  std::map<std::pair<int32_t, int32_t>, int> rows_of;
  for (std::size_t row = 0; row < tracks.size(); ++row) ++rows_of[{tracks.sensor[row], tracks.track[row]}];
  std::map<std::pair<int32_t, int32_t>, int32_t> renumber;
  std::map<int32_t, int32_t> next;
  for (const auto& [key, count] : rows_of)  // ordered by (sensor, old number)
    if (count >= kMinReports) renumber[key] = next[key.first]++;
  std::vector<uint8_t> keep(tracks.size(), 1);
  for (std::size_t row = 0; row < tracks.size(); ++row) {
    auto it = renumber.find({tracks.sensor[row], tracks.track[row]});
    keep[row] = it != renumber.end();
    if (keep[row]) tracks.track[row] = it->second;
  }
  keep_track_rows(tracks, keep);
}

int poisson_draw(CounterRng& rng, double mean) {
  if (mean <= 0.0) return 0;
  if (mean > 30.0) return std::max(0, static_cast<int>(std::lround(mean + std::sqrt(mean) * rng.normal())));
  const double limit = std::exp(-mean);
  int k = 0;
  double p = rng.uniform();
  while (p > limit) {
    ++k;
    p *= rng.uniform();
  }
  return k;
}

RecordingPlan plan_recording(const Scenario& sc, const std::vector<TargetTrajectory>& targets, uint64_t seed,
                             int run) {
  RecordingPlan plan;
  const RecordingSpec& g = sc.recording;
  if (g.is_default()) return plan;
  plan.active = true;
  int32_t base = 0;
  for (const auto& tr : targets) base = std::max(base, tr.id + 1);
  plan.phantom_base = base;
  const int d = spatial_dim(sc.layout);
  const RandomTargetSpec spec = phantom_spec(sc, targets);
  const uint64_t r = static_cast<uint64_t>(run);
  plan.sensors.resize(sc.sensors.size());
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) {
    SensorRecording& rec = plan.sensors[s];
    const double period = sc.sensors[s].period;
    const std::size_t n = targets.size();
    rec.seen.assign(n, 0);
    rec.window_start.assign(n, 0.0);
    rec.window_end.assign(n, sc.duration);
    for (std::size_t j = 0; j < n; ++j) {
      CounterRng rng(seed, r, stream_id(SimulationStream::kRecordingWindow, s), j);
      rec.seen[j] = rng.uniform() < g.p_seen;
      draw_window(g, sc.duration, period, rng, rec.window_start[j], rec.window_end[j]);
    }
    CounterRng count_rng(seed, r, stream_id(SimulationStream::kPhantomCount, s));
    const int phantoms = poisson_draw(count_rng, g.false_tracks * static_cast<double>(n));
    rec.phantom_start.assign(phantoms, 0.0);
    rec.phantom_end.assign(phantoms, sc.duration);
    for (int k = 0; k < phantoms; ++k) {
      const uint64_t kk = static_cast<uint64_t>(k);
      CounterRng rng(seed, r, stream_id(SimulationStream::kPhantomTrajectory, s), kk);
      CounterRng mrng(seed, r, stream_id(SimulationStream::kPhantomManoeuvre, s), kk);
      rec.phantoms.push_back(
          random_group_trajectories(spec, base + k, 1, sc.duration, sc.truth_step, d, rng, mrng).front());
      CounterRng wrng(seed, r, stream_id(SimulationStream::kPhantomWindow, s), kk);
      draw_window(g, sc.duration, period, wrng, rec.phantom_start[k], rec.phantom_end[k]);
    }
  }
  return plan;
}

void apply_recording(const RecordingPlan& plan, const Scenario& sc,
                     const std::vector<TargetTrajectory>& targets, SimulationResult& result) {
  if (!plan.active) return;
  std::unordered_map<int32_t, std::size_t> index_of_target;
  for (std::size_t j = 0; j < targets.size(); ++j) index_of_target[targets[j].id] = j;
  std::unordered_map<int32_t, std::size_t> index_of_sensor;
  for (std::size_t s = 0; s < sc.sensors.size(); ++s) index_of_sensor[sc.sensors[s].id] = s;

  TrackTable& tracks = result.tracks;
  // 1. Rows after the window end.
  std::vector<uint8_t> keep(tracks.size(), 1);
  for (std::size_t row = 0; row < tracks.size(); ++row) {
    const SensorRecording& rec = plan.sensors[index_of_sensor.at(tracks.sensor[row])];
    const int32_t id = tracks.truth[row];
    const double end = id >= plan.phantom_base ? rec.phantom_end[id - plan.phantom_base]
                                               : rec.window_end[index_of_target.at(id)];
    keep[row] = tracks.t[row] <= end + 1e-9;
  }
  keep_track_rows(tracks, keep);
  // 2. Tracks with fewer than kMinReports rows; 3. renumbering by rank per sensor.
  drop_short_tracks(tracks);
  // 4. Phantoms are not targets: −1 in the output.
  for (int32_t& id : tracks.truth)
    if (id >= plan.phantom_base) id = -1;
  for (int32_t& id : result.measurements.target)
    if (id >= plan.phantom_base) id = -1;
}

}  // namespace trackassoc
