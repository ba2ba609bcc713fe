// The front end of every association path; see engine/pipeline/front_end.hpp.
#include "engine/pipeline/front_end.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "engine/pipeline/pipeline.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

std::vector<double> common_time_grid(const TrackTable& tracks, std::span<const int32_t> sensor_ids,
                                     double period, bool span_union) {
  const std::size_t S = sensor_ids.size();
  std::vector<double> first(S, std::numeric_limits<double>::infinity()),
      last(S, -std::numeric_limits<double>::infinity());
  for (std::size_t r = 0; r < tracks.size(); ++r)
    for (std::size_t d = 0; d < S; ++d)
      if (tracks.sensor[r] == sensor_ids[d]) {
        first[d] = std::min(first[d], tracks.t[r]);
        last[d] = std::max(last[d], tracks.t[r]);
      }
  for (std::size_t d = 0; d < S; ++d)
    if (!std::isfinite(first[d]))
      throw InputError("/tracks: sensor " + std::to_string(sensor_ids[d]) +
                       " has no local tracks; the default pipeline (no --3d, --sd or --sparse, solver " +
                       "lr+ls, lr or exact) associates around such a sensor");
  const double start = span_union ? *std::min_element(first.begin(), first.end())
                                  : *std::max_element(first.begin(), first.end()) + period;
  const double end =
      span_union ? *std::max_element(last.begin(), last.end()) : *std::min_element(last.begin(), last.end());
  // The grid is allocated here: check it against the memory budget before the first push_back
  // (the tracks aligned to it are checked by align_sensors, over their spans).
  const double points = std::floor((end - start) / period) + 1.0;
  char what[160];
  std::snprintf(what, sizeof what,
                "the common time grid (%.4g times of period %g s over [%g, %g] s; see --common-period)",
                points, period, start, end);
  require_memory(bytes_of(points, sizeof(double)), what);
  std::vector<double> grid;
  const double eps = 1e-9 * std::max(1.0, std::fabs(end));
  for (int64_t k = 0;; ++k) {
    const double t = start + static_cast<double>(k) * period;
    if (t > end + eps) break;
    grid.push_back(t);
  }
  if (grid.empty()) {
    std::string ids;
    for (std::size_t d = 0; d < S; ++d) ids += (d ? ", " : "") + std::to_string(sensor_ids[d]);
    throw InputError("/tracks: sensors " + ids + " never report at a common time (common interval [" +
                     std::to_string(start) + ", " + std::to_string(end) + "] s with period " +
                     std::to_string(period) + " s)");
  }
  return grid;
}

namespace {

// The count rules of SensorRule::kThree, before any id is looked up.
void require_three_sensors(const TrackFile& file, const PipelineOptions& options) {
  const auto in_file = static_cast<int32_t>(file.sensors.size());
  if (in_file < 3)
    throw InputError("/sensors: three-sensor association needs at least 3 sensors, the file has " +
                     std::to_string(in_file));
  if (!options.sensors.empty() && options.sensors.size() != 3)
    throw InputError("--sensors: the 3-D pipeline takes exactly 3 sensor ids, got " +
                     std::to_string(options.sensors.size()) + "; " + std::to_string(options.sensors.size()) +
                     " sensors use the S-D formulation (associate --sd, engine/pipeline/pipeline_sd.hpp)");
  if (options.sensors.empty() && in_file > 3)
    throw InputError("/sensors: the file has " + std::to_string(in_file) +
                     " sensors and the 3-D pipeline takes three; give --sensors A,B,C, or associate them "
                     "all with the default pipeline (no --solver, or --solver lr+ls|lr|exact)");
}

}  // namespace

SensorSelection select_sensors(const TrackFile& file, const PipelineOptions& options, SensorRule rule) {
  SensorSelection sel;
  sel.file_sensors = static_cast<int32_t>(file.sensors.size());
  if (rule == SensorRule::kThree) require_three_sensors(file, options);
  std::map<int32_t, int32_t> column;
  for (int32_t s = 0; s < sel.file_sensors; ++s) column[file.sensors[s].id] = s;
  if (!options.sensors.empty()) {
    sel.ids = options.sensors;
  } else {
    const std::size_t n = rule == SensorRule::kThree ? 3 : file.sensors.size();
    for (std::size_t s = 0; s < n; ++s) sel.ids.push_back(file.sensors[s].id);
  }
  if (sel.ids.size() < 2)
    throw InputError("/sensors: association needs at least 2 sensors, the file has " +
                     std::to_string(sel.ids.size()));
  sel.period = options.common_period;
  for (int32_t id : sel.ids) {
    auto it = column.find(id);
    if (it == column.end())
      throw InputError("--sensors: sensor id " + std::to_string(id) + " is not in /sensors/id");
    sel.columns.push_back(it->second);
    if (options.common_period == 0.0) sel.period = std::max(sel.period, file.sensors[it->second].period);
  }
  require(sel.period > 0.0, "PipelineOptions.common_period", "the sensors' periods are not positive");
  return sel;
}

AlignedSensors align_sensors(const TrackFile& file, const PipelineOptions& options, SensorRule rule,
                             EmptySensors empty) {
  AlignedSensors p;
  const SensorSelection sel = select_sensors(file, options, rule);
  p.file_sensors = sel.file_sensors;
  p.dim = file.tracks.dim();
  if (empty == EmptySensors::kRefuse) {
    p.sensor_ids = sel.ids;
    p.sensor_columns = sel.columns;
  } else {
    // A sensor with no local tracks (down, or it saw nothing) is associated around: it takes no
    // part in the problem, and its column of the tuples stays -1 (issue 30).
    const std::set<int32_t> reporting(file.tracks.sensor.begin(), file.tracks.sensor.end());
    for (std::size_t k = 0; k < sel.ids.size(); ++k)
      if (reporting.count(sel.ids[k])) {
        p.sensor_ids.push_back(sel.ids[k]);
        p.sensor_columns.push_back(sel.columns[k]);
      } else {
        p.empty_sensor_ids.push_back(sel.ids[k]);
      }
    if (p.sensor_ids.size() < 2) {
      std::string none;
      for (int32_t id : p.empty_sensor_ids) none += (none.empty() ? "" : ", ") + std::to_string(id);
      throw InputError("/tracks: association needs the local tracks of at least 2 sensors; sensor" +
                       std::string(p.empty_sensor_ids.size() > 1 ? "s " : " ") + none + " of " +
                       std::to_string(sel.ids.size()) + " ha" + (p.empty_sensor_ids.size() > 1 ? "ve" : "s") +
                       " none");
    }
  }
  p.common_times = common_time_grid(file.tracks, p.sensor_ids, sel.period, options.span_union);
  // Each track is aligned over its span only: Σ spans cells (not tracks × grid), checked against
  // the memory budget before any is allocated.
  AlignedSize size;
  for (const int32_t id : p.sensor_ids) {
    const AlignedSize one = aligned_size(file.tracks, id, p.common_times, options.alignment);
    size.tracks += one.tracks;
    size.cells += one.cells;
  }
  char what[240];
  std::snprintf(
      what, sizeof what,
      "the aligned tracks (%zu local tracks over their spans: %lld cells of %zu bytes on the common "
      "time grid of %zu times of period %g s; see --common-period)",
      static_cast<size_t>(size.tracks), static_cast<long long>(size.cells),
      AlignedTracks::bytes_per_cell(p.dim), p.common_times.size(), sel.period);
  // Per cell: state, covariance, flag; per track: its number, truth, span (begin, offset) and valid
  // interval (first, last); beside what the process holds (the input).
  require_memory_beside_held(0.0,
                             static_cast<double>(size.cells) * AlignedTracks::bytes_per_cell(p.dim) +
                                 static_cast<double>(size.tracks) * (5 * sizeof(int32_t) + sizeof(int64_t)),
                             what);
  p.offset.assign(1, 0);
  for (int32_t s = 0; s < p.S(); ++s) {
    p.aligned.push_back(align_tracks(file.tracks, p.sensor_ids[s], p.common_times, options.alignment));
    const AlignedTracks& x = p.aligned.back();
    p.offset.push_back(p.offset.back() + x.n_tracks());
    for (int32_t i = 0; i < x.n_tracks(); ++i) {
      int32_t first = -1, last = -1;
      const AlignedTracks::Span sp = x.span(i);
      for (int32_t k = sp.begin; k < sp.end; ++k)
        if (x.valid[x.cell(i, k)]) {
          if (first < 0) first = k;
          last = k;
        }
      p.first_valid.push_back(first);
      p.last_valid.push_back(last);
    }
  }
  return p;
}

std::vector<UnfilteredSensor> unfiltered_sensors(const AlignedSensors& p) {
  std::vector<UnfilteredSensor> out;
  for (const AlignedTracks& a : p.aligned)  // tested (ratio > 0) and left without the lag terms
    if (!a.lag_terms && a.report_whiteness > 0.0) out.push_back({a.sensor, a.report_whiteness});
  return out;
}

}  // namespace trackassoc
