// Local tracking from unlabeled detections (issue 17 item 2): per sensor, the plots of each scan
// are taken from the ownship's frame into the world frame and fed to a GNN tracker
// (kernels/filters/gnn_tracker.hpp: clustering, χ²-gated JV assignment, CV Kalman filter, M-of-N
// confirmation, deletion after K misses). The confirmed tracks become schema v1 /tracks rows.
//
// Ownship frame: a plot (a, b) measured in the ownship's axes is, in the world frame,
//   p = o + R(ψ) (a, b)ᵀ,  R(ψ) = [cos ψ  −sin ψ; sin ψ  cos ψ],
// with o the ownship position and ψ the rotation from the ownship's axes to the world's (0 when the
// plots are already in world-aligned axes, as Autoferry's NED plots are). Only translation and
// rotation: the plots are positions, not polar measurements.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "kernels/core/types.hpp"
#include "kernels/filters/gnn_tracker.hpp"

namespace trackassoc {

// One scan of one sensor: plots in the ownship's axes.
struct DetectionScan {
  int32_t sensor = 0;
  double t = 0.0;                           // [s]
  double ownship_x = 0.0, ownship_y = 0.0;  // ownship position in the world frame [m]
  double ownship_rotation = 0.0;            // ψ [rad], see above
  std::vector<double> a, b;                 // plot coordinates in the ownship's axes [m]
};

struct LocalTrackingOptions {
  // Tracker options per sensor id; a sensor not listed uses `default_tracker`.
  std::map<int32_t, GnnTrackerOptions> per_sensor;
  GnnTrackerOptions default_tracker;
  void validate() const;  // every tracker's validate(), the field prefixed with the sensor
  const GnnTrackerOptions& tracker(int32_t sensor) const;
};

struct LocalTrackingSensorSummary {
  int32_t sensor = 0;
  int64_t scans = 0, plots = 0, clusters = 0;
  int32_t confirmed_tracks = 0;  // tracks confirmed over the run (the /tracks numbers 0..n-1)
  int64_t rows = 0;              // /tracks rows written
};

struct LocalTrackingSummary {
  std::vector<LocalTrackingSensorSummary> sensors;  // ascending sensor id
  double runtime_s = 0.0;
};

// World-frame position of plot (a, b) of `scan`.
void ownship_to_world(const DetectionScan& scan, double a, double b, double& x, double& y);

// Tracks the scans of every sensor that appears in `scans` (each sensor's scans in time order;
// scans of different sensors may interleave). Returns /tracks rows (layout x, y, vx, vy, truth -1)
// sorted by sensor, then track, then t.
TrackTable track_detections(const std::vector<DetectionScan>& scans, const LocalTrackingOptions& options,
                            LocalTrackingSummary* summary = nullptr);

}  // namespace trackassoc
