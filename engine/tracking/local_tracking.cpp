// Local tracking from detections (see local_tracking.hpp).
#include "engine/tracking/local_tracking.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <tuple>

#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void LocalTrackingOptions::validate() const {
  try {
    default_tracker.validate();
  } catch (const InputError& e) {
    throw InputError(std::string("tracker.") + e.what());
  }
  for (const auto& [sensor, o] : per_sensor) {
    try {
      o.validate();
    } catch (const InputError& e) {
      throw InputError("tracker[sensor " + std::to_string(sensor) + "]." + e.what());
    }
  }
}

const GnnTrackerOptions& LocalTrackingOptions::tracker(int32_t sensor) const {
  auto it = per_sensor.find(sensor);
  return it == per_sensor.end() ? default_tracker : it->second;
}

void ownship_to_world(const DetectionScan& scan, double a, double b, double& x, double& y) {
  const double c = std::cos(scan.ownship_rotation), s = std::sin(scan.ownship_rotation);
  x = scan.ownship_x + c * a - s * b;
  y = scan.ownship_y + s * a + c * b;
}

TrackTable track_detections(const std::vector<DetectionScan>& scans, const LocalTrackingOptions& options,
                            LocalTrackingSummary* summary) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  std::vector<int32_t> sensors;
  for (const DetectionScan& s : scans) sensors.push_back(s.sensor);
  std::sort(sensors.begin(), sensors.end());
  sensors.erase(std::unique(sensors.begin(), sensors.end()), sensors.end());

  TrackTable out(StateLayout::kXY_VXVY);
  LocalTrackingSummary sum;
  std::vector<double> x, y;
  for (const int32_t sensor : sensors) {
    GnnTracker tracker(options.tracker(sensor));
    LocalTrackingSensorSummary ss;
    ss.sensor = sensor;
    std::vector<GnnTrackRow> rows;
    for (const DetectionScan& s : scans) {
      if (s.sensor != sensor) continue;
      require(s.a.size() == s.b.size(), "detections", "a scan's plot coordinates differ in length");
      x.resize(s.a.size());
      y.resize(s.a.size());
      for (std::size_t i = 0; i < s.a.size(); ++i) ownship_to_world(s, s.a[i], s.b[i], x[i], y[i]);
      const GnnScanSummary g = tracker.step(s.t, x, y, rows);
      ++ss.scans;
      ss.plots += g.plots;
      ss.clusters += g.clusters;
    }
    ss.confirmed_tracks = tracker.confirmed_count();
    ss.rows = static_cast<int64_t>(rows.size());
    std::vector<std::size_t> order(rows.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) {
      return std::tie(rows[p].track, rows[p].t) < std::tie(rows[q].track, rows[q].t);
    });
    for (std::size_t j = 0; j < order.size(); ++j) {
      const GnnTrackRow& r = rows[order[j]];
      // Two scans at one time give two rows of one (track, t): keep the later (updated) one.
      if (j + 1 < order.size() && rows[order[j + 1]].track == r.track && rows[order[j + 1]].t == r.t)
        continue;
      out.push_back(sensor, r.track, r.t, r.x, r.P, -1);
    }
    sum.sensors.push_back(ss);
  }
  sum.runtime_s = seconds_since(start);
  if (summary) *summary = sum;
  return out;
}

}  // namespace trackassoc
