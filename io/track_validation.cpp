#include "io/track_validation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <unordered_set>

#include "io/isolated_run.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/local_track_rows.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc::track_validation {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

[[noreturn]] void fail(const std::string& file, const std::string& dataset, const std::string& what) {
  throw InputError(file + ": " + dataset + ": " + what);
}
[[noreturn]] void fail_row(const std::string& file, const std::string& dataset, std::size_t row,
                           const std::string& what) {
  fail(file, dataset, "row " + std::to_string(row) + ": " + what);
}

void check_length(const std::string& file, const std::string& dataset, std::size_t found,
                  std::size_t expected, const std::string& reference) {
  if (found != expected)
    fail(file, dataset,
         "expected " + std::to_string(expected) + " rows (as " + reference + "), found " +
             std::to_string(found));
}

// The least row r in [0, n) with bad(r), or n: the answer of the serial scan, found over blocks of
// rows in parallel (oneTBB) so that a 6-million-row file is checked on every core; each block stops
// at its first bad row or at one already found before it.
template <class Bad>
std::size_t first_bad_row(std::size_t n, Bad bad) {
  if (in_isolated_child()) {  // no task arena in a forked child (io/isolated_run.hpp)
    for (std::size_t r = 0; r < n; ++r)
      if (bad(r)) return r;
    return n;
  }
  std::atomic<std::size_t> first{n};
  parallel_for_range(n, std::size_t{1} << 15, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end && r < first.load(std::memory_order_relaxed); ++r)
      if (bad(r)) {
        std::size_t seen = first.load(std::memory_order_relaxed);
        while (r < seen && !first.compare_exchange_weak(seen, r, std::memory_order_relaxed)) {
        }
        return;
      }
  });
  return first.load();
}

void check_finite(const std::string& file, const std::string& dataset, const std::vector<double>& v) {
  const std::size_t r = first_bad_row(v.size(), [&](std::size_t i) { return !std::isfinite(v[i]); });
  if (r < v.size()) fail_row(file, dataset, r, "expected a finite value, found " + number(v[r]));
}

void check_finite_min(const std::string& file, const std::string& dataset, double v, std::size_t row,
                      double min) {
  if (!std::isfinite(v) || v < min)
    fail_row(file, dataset, row, "expected a finite value >= " + number(min) + ", found " + number(v));
}

// The /sensors ids, sorted and unique: a binary search per row.
std::vector<int32_t> sensor_ids(const std::vector<Sensor>& sensors) {
  std::vector<int32_t> ids;
  for (const Sensor& s : sensors) ids.push_back(s.id);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// A local track reports at most once per time: two rows with the same (sensor, track, t) are an
// error, naming both rows, whether the states differ (two different estimates of one track at one
// instant: which one the alignment would use is arbitrary) or not (a repeated row).
void check_unique_reports(const std::string& file, const TrackTable& t) {
  // Each local track's rows in time order, ties in row order (kernels/core/local_track_rows.hpp):
  // the first repeat met, tracks in (sensor, track) order, is the one that sorts first, and its two
  // rows are the lowest with that time.
  const LocalTrackRows tracks = local_track_rows(t);
  for (std::size_t k = 0; k < tracks.size(); ++k) {
    const std::span<const std::size_t> rows = tracks.rows(k);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const std::size_t a = rows[i - 1], b = rows[i];
      if (t.t[a] != t.t[b]) continue;
      bool same = true;
      for (const auto& c : t.state) same = same && c[a] == c[b];
      for (const auto& c : t.cov) same = same && c[a] == c[b];
      fail_row(file, "/tracks", b,
               "sensor " + std::to_string(t.sensor[b]) + ", track " + std::to_string(t.track[b]) +
                   ", t = " + number(t.t[b]) + " is also row " + std::to_string(a) +
                   (same ? " (the same state repeated)" : " with a different state") +
                   "; a local track reports at most once per time");
    }
  }
}

}  // namespace

void check_object_name(const std::string& file, const std::string& group, const std::string& name) {
  bool ok = !name.empty() && name != "." && name.find('/') == std::string::npos;
  for (unsigned char c : name) ok = ok && c >= 32 && c != 127;
  if (!ok)
    fail(file, group,
         "invalid name " + quoted_preview(name, 80) + " (non-empty, no '/', no control characters, not '.')");
}

std::string positive_definite_failure(const double* packed, int d) {
  double a[6][6];
  for (int r = 0, k = 0; r < d; ++r)
    for (int c = r; c < d; ++c, ++k) a[r][c] = a[c][r] = packed[k];
  for (int i = 0; i < d; ++i)
    if (!(a[i][i] > 0))
      return "diagonal element (" + std::to_string(i) + "," + std::to_string(i) + ") = " + number(a[i][i]) +
             " is not positive";
  // In-place Cholesky, lower triangle: a = L Lᵀ exists iff every pivot is positive.
  for (int j = 0; j < d; ++j) {
    double pivot = a[j][j];
    for (int k = 0; k < j; ++k) pivot -= a[j][k] * a[j][k];
    if (!(pivot > 0))
      return "Cholesky pivot " + std::to_string(j) + " = " + number(pivot) + " is not positive";
    const double l = std::sqrt(pivot);
    a[j][j] = l;
    for (int i = j + 1; i < d; ++i) {
      double v = a[i][j];
      for (int k = 0; k < j; ++k) v -= a[i][k] * a[j][k];
      a[i][j] = v / l;
    }
  }
  return "";
}

void check_sensors(const std::string& file, const std::vector<Sensor>& sensors) {
  std::set<int32_t> seen;
  for (std::size_t r = 0; r < sensors.size(); ++r) {
    const Sensor& s = sensors[r];
    if (!seen.insert(s.id).second)
      fail_row(file, "/sensors/id", r, "sensor id " + std::to_string(s.id) + " appears twice");
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(s.position[c]))
        fail_row(file, "/sensors/position", r,
                 "column " + std::to_string(c) + ": expected a finite value, found " + number(s.position[c]));
    check_finite_min(file, "/sensors/sigma_range", s.sigma_range, r, 0);
    check_finite_min(file, "/sensors/sigma_bearing", s.sigma_bearing, r, 0);
    check_finite_min(file, "/sensors/sigma_elevation", s.sigma_elevation, r, 0);
    check_finite_min(file, "/sensors/period", s.period, r, 0);
    check_finite_min(file, "/sensors/offset", s.offset, r, -std::numeric_limits<double>::max());
    check_finite_min(file, "/sensors/clutter_rate", s.clutter_rate, r, 0);
    check_finite_min(file, "/sensors/reliability", s.reliability, r, 0);
    if (!(s.p_detect >= 0 && s.p_detect <= 1))
      fail_row(file, "/sensors/p_detect", r, "expected a value in [0, 1], found " + number(s.p_detect));
  }
}

void check_tracks(const std::string& file, const TrackTable& t, const std::vector<Sensor>& sensors) {
  const std::size_t n = t.sensor.size();
  const int d = t.dim();
  const std::string ref = "/tracks/sensor";
  check_length(file, "/tracks/track", t.track.size(), n, ref);
  check_length(file, "/tracks/t", t.t.size(), n, ref);
  check_length(file, "/tracks/truth", t.truth.size(), n, ref);
  if (static_cast<int>(t.state.size()) != d)
    fail(file, "/tracks/state", "expected " + std::to_string(d) + " columns");
  if (static_cast<int>(t.cov.size()) != packed_size(d))
    fail(file, "/tracks/cov", "expected " + std::to_string(packed_size(d)) + " columns");
  for (const auto& c : t.state) check_length(file, "/tracks/state", c.size(), n, ref);
  for (const auto& c : t.cov) check_length(file, "/tracks/cov", c.size(), n, ref);

  const std::vector<int32_t> ids = sensor_ids(sensors);
  auto known = [&](std::size_t r) { return std::binary_search(ids.begin(), ids.end(), t.sensor[r]); };
  const std::size_t bad_key =
      first_bad_row(n, [&](std::size_t r) { return !known(r) || t.track[r] < 0 || t.truth[r] < -1; });
  if (bad_key < n) {
    const std::size_t r = bad_key;
    if (!known(r))
      fail_row(file, "/tracks/sensor", r, "sensor " + std::to_string(t.sensor[r]) + " is not in /sensors/id");
    if (t.track[r] < 0)
      fail_row(file, "/tracks/track", r, "expected a track number >= 0, found " + std::to_string(t.track[r]));
    fail_row(file, "/tracks/truth", r, "expected a target id >= -1, found " + std::to_string(t.truth[r]));
  }
  check_finite(file, "/tracks/t", t.t);
  const char* names[] = {"x", "y", "z", "vx", "vy", "vz"};
  const int order4[] = {0, 1, 3, 4}, order6[] = {0, 1, 2, 3, 4, 5};
  for (int c = 0; c < d; ++c) {
    const std::vector<double>& x = t.state[c];
    const std::size_t r = first_bad_row(n, [&](std::size_t i) { return !std::isfinite(x[i]); });
    if (r < n)
      fail_row(file, "/tracks/state", r,
               "column " + std::to_string(c) + " (" + names[d == 4 ? order4[c] : order6[c]] +
                   "): expected a finite value, found " + number(x[r]));
  }
  const int p = packed_size(d);
  auto packed_row = [&](std::size_t r, double* packed) {
    for (int k = 0; k < p; ++k) packed[k] = t.cov[k][r];
  };
  const std::size_t bad_cov = first_bad_row(n, [&](std::size_t r) {
    double packed[21];
    packed_row(r, packed);
    for (int k = 0; k < p; ++k)
      if (!std::isfinite(packed[k])) return true;
    return !positive_definite_failure(packed, d).empty();
  });
  if (bad_cov < n) {
    double packed[21];
    packed_row(bad_cov, packed);
    for (int k = 0; k < p; ++k)
      if (!std::isfinite(packed[k]))
        fail_row(file, "/tracks/cov", bad_cov,
                 "column " + std::to_string(k) + ": expected a finite value, found " + number(packed[k]));
    fail_row(file, "/tracks/cov", bad_cov,
             "covariance is not positive definite: " + positive_definite_failure(packed, d));
  }
  check_unique_reports(file, t);
}

void check_recording_info(const std::string& file, const RecordingInfo& info) {
  if (!info.frame.empty() && info.frame != "ENU" && info.frame != "NED")
    fail(file, "/tracks", "attribute frame: expected \"ENU\" or \"NED\", found \"" + info.frame + "\"");
  if (!info.frame_origin) return;
  if (info.frame.empty())
    fail(file, "/tracks", "attribute frame_origin_lat_deg given without attribute frame");
  const auto& o = *info.frame_origin;
  if (!(o[0] >= -90 && o[0] <= 90))
    fail(file, "/tracks",
         "attribute frame_origin_lat_deg: expected a latitude in [-90, 90], found " + number(o[0]));
  if (!(o[1] >= -180 && o[1] <= 360))
    fail(file, "/tracks",
         "attribute frame_origin_lon_deg: expected a longitude in [-180, 360], found " + number(o[1]));
  if (!std::isfinite(o[2]))
    fail(file, "/tracks", "attribute frame_origin_alt_m: expected a finite height, found " + number(o[2]));
}

void check_truth(const std::string& file, const TruthTable& t) {
  const std::size_t n = t.target.size();
  check_length(file, "/truth/t", t.t.size(), n, "/truth/target");
  if (static_cast<int>(t.state.size()) != state_dim(t.layout))
    fail(file, "/truth/state", "expected " + std::to_string(state_dim(t.layout)) + " columns");
  for (const auto& c : t.state) check_length(file, "/truth/state", c.size(), n, "/truth/target");
  for (std::size_t r = 0; r < n; ++r)
    if (t.target[r] < 0)
      fail_row(file, "/truth/target", r, "expected a target id >= 0, found " + std::to_string(t.target[r]));
  check_finite(file, "/truth/t", t.t);
  for (const auto& c : t.state) check_finite(file, "/truth/state", c);
}

void check_measurements(const std::string& file, const Measurements& m, const std::vector<Sensor>& sensors) {
  const std::size_t n = m.sensor.size();
  const std::string ref = "/measurements/sensor";
  check_length(file, "/measurements/t", m.t.size(), n, ref);
  check_length(file, "/measurements/range", m.range.size(), n, ref);
  check_length(file, "/measurements/bearing", m.bearing.size(), n, ref);
  check_length(file, "/measurements/target", m.target.size(), n, ref);
  if (!m.elevation.empty())
    check_length(file, "/measurements/elevation", m.elevation.size(), n, ref + " (or 0 for 2-D)");
  const std::vector<int32_t> ids = sensor_ids(sensors);
  for (std::size_t r = 0; r < n; ++r) {
    if (!std::binary_search(ids.begin(), ids.end(), m.sensor[r]))
      fail_row(file, "/measurements/sensor", r,
               "sensor " + std::to_string(m.sensor[r]) + " is not in /sensors/id");
    if (m.target[r] < -1)
      fail_row(file, "/measurements/target", r,
               "expected a target id >= -1 (-1 = clutter), found " + std::to_string(m.target[r]));
    check_finite_min(file, "/measurements/range", m.range[r], r, 0);
  }
  check_finite(file, "/measurements/t", m.t);
  check_finite(file, "/measurements/bearing", m.bearing);
  check_finite(file, "/measurements/elevation", m.elevation);
}

void check_measurement_noise(const std::string& file, const Measurements& m,
                             const std::vector<Sensor>& sensors, bool three_d) {
  const std::set<int32_t> reporting(m.sensor.begin(), m.sensor.end());
  for (std::size_t r = 0; r < sensors.size(); ++r) {
    const Sensor& s = sensors[r];
    if (!reporting.count(s.id)) continue;
    auto need_positive = [&](const char* dataset, double v) {
      if (!(v > 0))
        fail_row(file, dataset, r,
                 "sensor " + std::to_string(s.id) +
                     " reports /measurements, so its filters need σ > 0, found " + number(v));
    };
    need_positive("/sensors/sigma_range", s.sigma_range);
    need_positive("/sensors/sigma_bearing", s.sigma_bearing);
    if (three_d) need_positive("/sensors/sigma_elevation", s.sigma_elevation);
  }
}

void check_association(const std::string& file, const AssociationRecord& a,
                       const std::vector<Sensor>& sensors, const TrackTable& tracks) {
  check_object_name(file, "/associations", a.name);
  const std::string g = "/associations/" + a.name;
  const std::size_t s = sensors.size();
  if (a.num_sensors != static_cast<int32_t>(s))
    fail(file, g + "/tuples",
         "expected " + std::to_string(s) + " columns (one per sensor, in /sensors order), found " +
             std::to_string(a.num_sensors));
  const std::size_t k = a.cost.size();
  if (a.tuples.size() != k * s)
    fail(file, g + "/tuples",
         "expected " + std::to_string(k) + " rows (as " + g + "/cost) of " + std::to_string(s) +
             " columns, found " + std::to_string(a.tuples.size()) + " values");
  std::map<int32_t, std::size_t> column_of;
  for (std::size_t c = 0; c < s; ++c) column_of[sensors[c].id] = c;
  std::vector<std::unordered_set<int32_t>> reported(s);
  for (std::size_t r = 0; r < tracks.sensor.size(); ++r) {
    auto it = column_of.find(tracks.sensor[r]);
    if (it != column_of.end()) reported[it->second].insert(tracks.track[r]);
  }
  for (std::size_t r = 0; r < k; ++r)
    for (std::size_t c = 0; c < s; ++c) {
      const int32_t v = a.tuples[r * s + c];
      if (v != kNoTrack && !reported[c].count(v))
        fail_row(file, g + "/tuples", r,
                 "column " + std::to_string(c) + " (sensor " + std::to_string(sensors[c].id) +
                     "): expected -1 or a track number of that sensor in /tracks/track, found " +
                     std::to_string(v));
    }
  if (a.energy_rows < 0 || a.energy_cols < 0 ||
      a.energy.size() != static_cast<std::size_t>(a.energy_rows) * static_cast<std::size_t>(a.energy_cols))
    fail(file, g + "/energy",
         "expected " + std::to_string(a.energy_rows) + "x" + std::to_string(a.energy_cols) +
             " values, found " + std::to_string(a.energy.size()));
  if (!a.restarts.consistent())
    fail(file, g + "/restarts",
         "expected every column to have " + std::to_string(a.restarts.size()) + " rows (as " + g +
             "/restarts/restart)");
  for (std::size_t r = 0; r < a.restarts.valid_raw.size(); ++r)
    if (a.restarts.valid_raw[r] != 0 && a.restarts.valid_raw[r] != 1)
      fail_row(file, g + "/restarts/valid_raw", r,
               "expected 0 or 1, found " + std::to_string(a.restarts.valid_raw[r]));
  if (a.unassociated.size() % 2 != 0)
    fail(file, g + "/unassociated", "expected rows of 2 values (sensor id, track)");
  for (std::size_t r = 0; r < a.unassociated.size() / 2; ++r) {
    const int32_t sensor = a.unassociated[2 * r], track = a.unassociated[2 * r + 1];
    auto it = column_of.find(sensor);
    if (it == column_of.end())
      fail_row(file, g + "/unassociated", r,
               "column 0: expected a sensor id of /sensors, found " + std::to_string(sensor));
    if (!reported[it->second].count(track))
      fail_row(file, g + "/unassociated", r,
               "column 1: expected a track number of sensor " + std::to_string(sensor) +
                   " in /tracks/track, found " + std::to_string(track));
  }
}

void check_metrics(const std::string& file, const MetricsRecord& m) {
  check_object_name(file, "/metrics", m.name);
  for (const auto& entry : m.tables) check_object_name(file, "/metrics/" + m.name, entry.first);
}

}  // namespace trackassoc::track_validation
