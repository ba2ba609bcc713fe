// The Autoferry benchmark end to end (see autoferry.hpp).
#include "engine/studies/autoferry/autoferry.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

// Median interval between consecutive scans of `sensor` (its Sensor::period).
double median_scan_interval(const AutoferryScenario& sc, int32_t sensor) {
  std::vector<double> dt;
  double last = std::numeric_limits<double>::quiet_NaN();
  for (const AutoferryScan& s : sc.scans) {
    if (s.sensor != sensor) continue;
    if (std::isfinite(last) && s.t > last) dt.push_back(s.t - last);
    last = s.t;
  }
  if (dt.empty()) return 1.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

// The rows of the tracks that span at least `min_duration` [s] (first to last row).
TrackTable drop_short_tracks(const TrackTable& in, double min_duration) {
  std::map<std::pair<int32_t, int32_t>, std::pair<double, double>> span;
  for (std::size_t i = 0; i < in.size(); ++i) {
    auto [it, fresh] =
        span.emplace(std::make_pair(in.sensor[i], in.track[i]), std::make_pair(in.t[i], in.t[i]));
    if (!fresh) it->second = {std::min(it->second.first, in.t[i]), std::max(it->second.second, in.t[i])};
  }
  TrackTable out(in.layout);
  for (std::size_t i = 0; i < in.size(); ++i) {
    const auto& sp = span[{in.sensor[i], in.track[i]}];
    if (sp.second - sp.first < min_duration) continue;
    out.sensor.push_back(in.sensor[i]);
    out.track.push_back(in.track[i]);
    out.t.push_back(in.t[i]);
    out.truth.push_back(in.truth[i]);
    for (std::size_t c = 0; c < in.state.size(); ++c) out.state[c].push_back(in.state[c][i]);
    for (std::size_t c = 0; c < in.cov.size(); ++c) out.cov[c].push_back(in.cov[c][i]);
  }
  return out;
}

}  // namespace

LocalTrackingOptions AutoferryOptions::default_tracking() {
  LocalTrackingOptions o;
  GnnTrackerOptions lidar, radar;
  lidar.measurement_sigma = 3.0;
  lidar.delete_misses = 10;  // 5 s at 0.5 s scans
  radar.measurement_sigma = 5.0;
  radar.delete_misses = 3;                                 // 5 s at 1.68 s scans
  lidar.cluster_distance = radar.cluster_distance = 15.0;  // half Gunnerus' 31 m hull
  lidar.initiate_in_gate = false;  // no duplicate tracks of one hull (the radar: one plot per hull)
  o.per_sensor = {{kAutoferryLidar, lidar}, {kAutoferryRadar, radar}};
  o.default_tracker = lidar;
  return o;
}

AssociatorOptions AutoferryOptions::default_association() {
  AssociatorOptions o;
  o.pipeline.alignment.extent_sigma = 8.0;
  o.segments.duplicate_sensors = {kAutoferryLidar};  // a hull in two lidar clusters: two tracks
  return o;                                          // segments: on, the default
}

void AutoferryOptions::validate() const {
  tracking.validate();
  association.validate();
  require(std::isfinite(label_distance) && label_distance > 0, "label_distance",
          "expected a finite value > 0 [m]");
  require(label_fraction > 0 && label_fraction <= 1, "label_fraction", "expected a value in (0, 1]");
  require(std::isfinite(min_overlap_s) && min_overlap_s >= 0, "min_overlap_s",
          "expected a finite value >= 0 [s]");
}

nlohmann::json AutoferryOptions::to_json() const {
  nlohmann::json trackers = nlohmann::json::object();
  for (const auto& [sensor, t] : tracking.per_sensor)
    trackers[std::to_string(sensor)] = {
        {"measurement_sigma", t.measurement_sigma},     {"process_noise", t.process_noise},
        {"initial_speed_sigma", t.initial_speed_sigma}, {"gate_probability", t.gate_probability},
        {"cluster_distance", t.cluster_distance},       {"confirm_hits", t.confirm_hits},
        {"confirm_window", t.confirm_window},           {"delete_misses", t.delete_misses},
        {"initiate_in_gate", t.initiate_in_gate}};
  return {{"trackers", trackers},
          {"label_distance", label_distance},
          {"label_fraction", label_fraction},
          {"min_overlap_s", min_overlap_s},
          {"min_track_duration_s", min_track_duration_s},
          {"association",
           {{"pipeline", association.pipeline.to_json()},
            {"solver", association.solver},
            {"segments", association.segments.to_json()}}}};
}

std::vector<TrackLabel> label_local_tracks(const TrackTable& tracks, const TruthTable& truth, double distance,
                                           double fraction) {
  // Truth per vessel, sorted by time.
  std::map<int32_t, std::vector<std::array<double, 3>>> series;  // t, x, y
  for (std::size_t i = 0; i < truth.size(); ++i)
    series[truth.target[i]].push_back({truth.t[i], truth.state[0][i], truth.state[1][i]});
  for (auto& [v, s] : series) std::sort(s.begin(), s.end());
  auto near = [&](const std::vector<std::array<double, 3>>& s, double t, double x, double y) {
    if (s.empty() || t < s.front()[0] || t > s.back()[0]) return false;
    auto it = std::lower_bound(s.begin(), s.end(), t,
                               [](const std::array<double, 3>& a, double v) { return a[0] < v; });
    double px = (*it)[1], py = (*it)[2];
    if ((*it)[0] > t && it != s.begin()) {
      const auto& a = *(it - 1);
      const double w = (t - a[0]) / ((*it)[0] - a[0]);
      px = a[1] + w * ((*it)[1] - a[1]);
      py = a[2] + w * ((*it)[2] - a[2]);
    }
    return std::hypot(x - px, y - py) <= distance;
  };
  std::map<std::pair<int32_t, int32_t>, std::vector<std::size_t>> rows;
  for (std::size_t i = 0; i < tracks.size(); ++i) rows[{tracks.sensor[i], tracks.track[i]}].push_back(i);
  std::vector<TrackLabel> out;
  for (const auto& [key, idx] : rows) {
    TrackLabel l;
    l.sensor = key.first;
    l.track = key.second;
    l.rows = static_cast<int64_t>(idx.size());
    l.t_first = tracks.t[idx.front()];
    l.t_last = tracks.t[idx.front()];
    for (std::size_t i : idx) {
      l.t_first = std::min(l.t_first, tracks.t[i]);
      l.t_last = std::max(l.t_last, tracks.t[i]);
    }
    double best = -1.0;
    for (const auto& [v, s] : series) {
      int64_t n = 0;
      for (std::size_t i : idx) n += near(s, tracks.t[i], tracks.state[0][i], tracks.state[1][i]);
      const double f = static_cast<double>(n) / static_cast<double>(idx.size());
      if (f >= fraction && f > best) best = f, l.label = v;  // map order: ties go to the smaller id
    }
    out.push_back(l);
  }
  return out;
}

TrackFile autoferry_track_file(const AutoferryScenario& sc, const AutoferryOptions& options,
                               LocalTrackingSummary* summary) {
  options.validate();
  std::vector<DetectionScan> scans;
  for (const AutoferryScan& s : sc.scans) {
    if (s.sensor != kAutoferryLidar && s.sensor != kAutoferryRadar) continue;
    DetectionScan d;
    d.sensor = s.sensor;
    d.t = s.t;
    d.ownship_x = s.ownship[0];  // north
    d.ownship_y = s.ownship[1];  // east
    d.a = s.north;
    d.b = s.east;
    scans.push_back(std::move(d));
  }
  TrackFile file;
  file.tracks =
      drop_short_tracks(track_detections(scans, options.tracking, summary), options.min_track_duration_s);
  for (const int32_t id : {kAutoferryLidar, kAutoferryRadar}) {
    Sensor s;
    s.id = id;
    s.position = {0, 0, 0};
    s.sigma_range = options.tracking.tracker(id).measurement_sigma;
    s.sigma_bearing = 0.0;
    s.period = median_scan_interval(sc, id);
    file.sensors.push_back(s);
  }
  const std::vector<TrackLabel> labels =
      label_local_tracks(file.tracks, sc.truth, options.label_distance, options.label_fraction);
  std::map<std::pair<int32_t, int32_t>, int32_t> label_of;
  for (const TrackLabel& l : labels) label_of[{l.sensor, l.track}] = l.label;
  for (std::size_t i = 0; i < file.tracks.size(); ++i)
    file.tracks.truth[i] = label_of[{file.tracks.sensor[i], file.tracks.track[i]}];
  file.truth = sc.truth;
  file.recording.frame = "NED";
  file.recording.frame_origin = kPirenOrigin;
  nlohmann::json imp = {{"source", "autoferry"},
                        {"scenario", sc.number},
                        {"t0_unix", sc.t0_unix},
                        {"sensors", {{"1", "lidar"}, {"2", "radar"}}},
                        {"tracker", "GNN (kernels/filters/gnn_tracker.hpp)"},
                        {"options", options.to_json()}};
  file.recording.import_json = imp.dump();
  // The ownship carries the sensors, so a fixed position means nothing; σ_range holds the
  // tracker's Cartesian σ, not a range σ.
  file.recording.sensors_unknown = "position,sigma_range,sigma_bearing,offset,p_detect";
  return file;
}

int32_t track_breaks(const std::vector<TrackLabel>& labels, int32_t sensor) {
  std::map<int32_t, int32_t> per_vessel;
  for (const TrackLabel& l : labels)
    if (l.sensor == sensor && l.label >= 0) ++per_vessel[l.label];
  int32_t breaks = 0;
  for (const auto& [v, n] : per_vessel) breaks += n - 1;
  return breaks;
}

void PairScore::add(const PairScore& o) {
  true_pairs += o.true_pairs;
  predicted += o.predicted;
  correct += o.correct;
  unlabelled_predicted += o.unlabelled_predicted;
  for (const auto& [v, n] : o.correct_by_vessel) correct_by_vessel[v] += n;
  for (const auto& [v, n] : o.false_by_vessel) false_by_vessel[v] += n;
}

double PairScore::precision() const {
  const int64_t n = predicted - unlabelled_predicted;
  return n > 0 ? static_cast<double>(correct) / static_cast<double>(n)
               : std::numeric_limits<double>::quiet_NaN();
}
double PairScore::recall() const {
  return true_pairs > 0 ? static_cast<double>(correct) / static_cast<double>(true_pairs)
                        : std::numeric_limits<double>::quiet_NaN();
}

PairScore score_radar_lidar_pairs(const TrackFile& file, const AssociationRecord& rec,
                                  const std::vector<TrackLabel>& labels, double min_overlap_s) {
  int lidar_col = -1, radar_col = -1;
  for (std::size_t s = 0; s < file.sensors.size(); ++s) {
    if (file.sensors[s].id == kAutoferryLidar) lidar_col = static_cast<int>(s);
    if (file.sensors[s].id == kAutoferryRadar) radar_col = static_cast<int>(s);
  }
  require(lidar_col >= 0 && radar_col >= 0 && rec.num_sensors == static_cast<int32_t>(file.sensors.size()),
          "association", "expected tuples over the lidar (1) and radar (2) sensors");
  std::map<int32_t, const TrackLabel*> lidar, radar;
  for (const TrackLabel& l : labels) (l.sensor == kAutoferryLidar ? lidar : radar)[l.track] = &l;
  auto overlap = [](const TrackLabel& a, const TrackLabel& b) {
    return std::min(a.t_last, b.t_last) - std::max(a.t_first, b.t_first);
  };
  PairScore score;
  for (const auto& [r, lr] : radar)
    for (const auto& [l, ll] : lidar)
      if (lr->label >= 0 && lr->label == ll->label && overlap(*lr, *ll) >= min_overlap_s) ++score.true_pairs;
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    const int32_t l = rec.tuples[k * rec.num_sensors + lidar_col],
                  r = rec.tuples[k * rec.num_sensors + radar_col];
    if (l < 0 || r < 0 || !lidar.count(l) || !radar.count(r)) continue;
    const TrackLabel &a = *lidar[l], &b = *radar[r];
    if (overlap(a, b) < min_overlap_s) continue;
    ++score.predicted;
    if (a.label < 0 && b.label < 0) {
      ++score.unlabelled_predicted;
    } else if (a.label == b.label) {
      ++score.correct;
      ++score.correct_by_vessel[a.label];
    } else {
      if (a.label >= 0) ++score.false_by_vessel[a.label];
      if (b.label >= 0) ++score.false_by_vessel[b.label];
    }
  }
  return score;
}

AutoferryScenarioResult run_autoferry_scenario(const std::string& root, int scenario,
                                               const AutoferryOptions& options,
                                               const std::string& output_path) {
  const auto start = std::chrono::steady_clock::now();
  AutoferryScenarioResult res;
  res.scenario = scenario;
  const AutoferryScenario sc = read_autoferry_scenario(root, scenario);
  TrackFile file = autoferry_track_file(sc, options, &res.tracking);
  res.labels = label_local_tracks(file.tracks, sc.truth, options.label_distance, options.label_fraction);
  const auto associator = make_associator(options.association);
  const AssociationOutcome outcome = associator->associate(file);
  res.association = outcome.summary;
  res.pairs = score_radar_lidar_pairs(file, outcome.record, res.labels, options.min_overlap_s);
  if (!output_path.empty()) {
    store_outcome(file, outcome);
    write_track_file(output_path, file);
    res.output = output_path;
  }
  res.seconds = seconds_since(start);
  return res;
}

AutoferryExperimentResult run_autoferry_experiment(const std::string& root, const AutoferryOptions& options,
                                                   const std::string& output_dir) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  if (!output_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(output_dir, ec);
    require(!ec && std::filesystem::is_directory(output_dir), "--output",
            "cannot create the folder '" + output_dir + "'");
  }
  AutoferryExperimentResult out;
  for (const int n : kAutoferryScenarios) {
    const std::string path = output_dir.empty() ? "" : output_dir + "/scenario" + std::to_string(n) + ".h5";
    out.scenarios.push_back(run_autoferry_scenario(root, n, options, path));
    out.total.add(out.scenarios.back().pairs);
  }
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace trackassoc
