// Hand-made track files for the fragment stitching tests (engine/pipeline/track_stitching.hpp):
// segments of constant velocity on two sensors, the tuples of one member each, and the closed forms
// of the midpoint prediction that the tests' hand calculations use (for reports with diagonal P and
// equal halves of the gap, the forward and backward cross terms cancel, so S is diagonal).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "engine/pipeline/track_stitching.hpp"
#include "io/track_file.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc::stitching_test {

struct Segment {
  int32_t sensor = 0, track = 0;
  double t0 = 0, t1 = 0, x0 = 0, vx = 0, y0 = 0, vy = 0;  // position at t = 0 and velocity
};

// Two sensors (ids 0, 1), reports every 2 s on each segment, P = diag(100², 100², 1, 1).
inline TrackFile hand_made(const std::vector<Segment>& segments) {
  TrackFile f;
  for (int32_t id : {0, 1}) {
    Sensor s;
    s.id = id;
    f.sensors.push_back(s);
  }
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 1e4, 1e4, 1.0, 1.0;
  for (const auto& g : segments)
    for (double t = g.t0; t <= g.t1 + 1e-9; t += 2.0)
      f.tracks.push_back(g.sensor, g.track, t, Eigen::Vector4d(g.x0 + g.vx * t, g.y0 + g.vy * t, g.vx, g.vy),
                         P, -1);
  return f;
}

// A far target that coexists with everything (never a candidate) and spans the "different
// targets" box: its start (−60 km, −60 km, −300 m/s, −300 m/s).
inline const Segment kBackground{1, 99, 0, 200, -60000, -300, -60000, -300};

// One tuple of one member per (sensor, track) given, target numbers 0, 1, ...
inline AssociationRecord singletons(const std::vector<std::pair<int32_t, int32_t>>& keys) {
  AssociationRecord rec;
  rec.num_sensors = 2;
  for (const auto& [sensor, track] : keys) {
    rec.tuples.push_back(sensor == 0 ? track : -1);
    rec.tuples.push_back(sensor == 1 ? track : -1);
    rec.target.push_back(static_cast<int32_t>(rec.target.size()));
  }
  return rec;
}

// The quiet model alone with σ_a = 0 (and the gate on it).
inline TrackStitchOptions no_manoeuvre() {
  TrackStitchOptions o;
  o.manoeuvre_sigma = o.turn_sigma = 0.0;
  o.turn_probability = 0.0;
  return o;
}

inline const double kGate = chi_square_quantile(0.9999, 4);  // χ²₄(0.9999) ≈ 23.51
inline const double kLog2Pi4 = 4.0 * std::log(2.0 * std::numbers::pi);

// By hand, σ_a = 0, a gap of 20 s (each end predicted 10 s to the midpoint): along x the forward
// prediction is [[1e4 + 100, 10], [10, 1]], the backward one [[1e4 + 100, −10], [−10, 1]], so
// S = diag(20200, 2) along x and (both y states 0 in these files) S = diag(20200, 2) along y too.
// A start displaced by δ along x (same velocity) gives m² = δ²/20200, and
// ln det(2πS) = 4 ln 2π + 2 ln(20200·2).
inline double m2_of_offset(double delta) { return delta * delta / 20200.0; }
inline const double kLogDet20 = kLog2Pi4 + 2.0 * std::log(20200.0 * 2.0);
inline double critical_offset() { return std::sqrt(20200.0 * kGate); }

// ln V of the box of the start states, by hand from the segments' start states.
inline double log_volume(const std::vector<std::array<double, 4>>& starts) {
  double v = 0.0;
  for (int i = 0; i < 4; ++i) {
    double lo = 1e300, hi = -1e300;
    for (const auto& s : starts) lo = std::min(lo, s[i]), hi = std::max(hi, s[i]);
    v += std::log(std::max(hi - lo, 1.0));
  }
  return v;
}

}  // namespace trackassoc::stitching_test
