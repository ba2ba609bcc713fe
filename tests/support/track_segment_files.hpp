// Track files for the segment pass's tests (tests/engine/pipeline/test_track_segments*.cpp):
// recorded_sync's first two sensors with tracks broken, staggered or lost at given times, and the
// checks those tests share.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/track_file.hpp"

namespace trackassoc::testing_support {

constexpr int32_t kRenumber = 1000;  // the second segment of track k is track k + kRenumber

// recorded_sync with its first two sensors; sensor c (0, 1) loses every track between t_end[c] and
// t_start[c] (a gap, or an overlap when t_start < t_end), the rows from t_start[c] on taking a new
// number (never: both 1e9).
inline TrackFile staggered_file(std::array<double, 2> t_end, std::array<double, 2> t_start) {
  const Scenario sc = load_scenario("recorded_sync");
  TrackFile f = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const std::array<int32_t, 2> ids{f.sensors[0].id, f.sensors[1].id};
  f.sensors.resize(2);
  TrackTable out(f.tracks.layout);
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r];
    const int c = s == ids[0] ? 0 : (s == ids[1] ? 1 : -1);
    if (c < 0) continue;
    const double t = f.tracks.t[r];
    const auto x = f.tracks.state_at(r);
    const auto P = f.tracks.cov_at(r);
    if (t < t_end[c]) out.push_back(s, f.tracks.track[r], t, x, P, f.tracks.truth[r]);
    if (t >= t_start[c]) out.push_back(s, f.tracks.track[r] + kRenumber, t, x, P, f.tracks.truth[r]);
  }
  f.tracks = out;
  f.measurements.reset();   // of the dropped sensor too
  f.scenario_json.clear();  // a recorded track set now
  return f;
}

// Sensor 1 broken between t_end and t_start, sensor 0 whole.
inline TrackFile broken_file(double t_end, double t_start) {
  return staggered_file({1e9, t_end}, {1e9, t_start});
}

inline AssociationOutcome associate(const TrackFile& f, bool segments, double max_overlap = 2.0,
                                    std::vector<int32_t> duplicate_sensors = {}, SegmentOptions so = {}) {
  AssociatorOptions o;
  o.segments = so;
  o.segments.enabled = segments;
  o.segments.max_overlap_s = max_overlap;
  o.segments.duplicate_sensors = std::move(duplicate_sensors);
  return make_associator(o)->associate(f);
}

inline std::map<std::pair<int32_t, int32_t>, std::pair<double, double>> spans(const TrackFile& f) {
  std::map<std::pair<int32_t, int32_t>, std::pair<double, double>> out;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    auto [it, fresh] = out.emplace(std::make_pair(f.tracks.sensor[r], f.tracks.track[r]),
                                   std::make_pair(f.tracks.t[r], f.tracks.t[r]));
    it->second.first = std::min(it->second.first, f.tracks.t[r]);
    it->second.second = std::max(it->second.second, f.tracks.t[r]);
  }
  return out;
}

// The segment pass on f: every target of the plain assignment's metrics mp correct, no false
// tuple, and the pass's summary present.
inline AssociationOutcome segments_make_every_target_correct(const TrackFile& f,
                                                             const AssociationMetrics& mp) {
  AssociationOutcome seg = associate(f, true);
  const AssociationMetrics m = evaluate_association(f.tracks, f.sensors, seg.record);
  EXPECT_EQ(m.targets, mp.targets);
  EXPECT_EQ(m.correct, m.targets);
  EXPECT_EQ(m.false_tuples, 0);
  EXPECT_TRUE(seg.summary.segments.has_value());
  return seg;
}

// recorded_sync's first two sensors (scans every 4 s from 0 s); sensor 1's tracker loses every
// target after its report at 32 s: the old track goes on reporting at the times of `after` (its
// state at 32 s moved by constant velocity, every covariance entry the given factor times the
// report at 32 s's), while the successor (number + kRenumber) reports the target from 36 s on.
inline TrackFile lost_file(const std::map<double, double>& after) {
  TrackFile f = broken_file(1e9, 1e9);  // the two sensors, unbroken
  const int32_t lost = f.sensors[1].id;
  TrackTable out(f.tracks.layout);
  std::map<int32_t, std::size_t> last_update;  // sensor 1's track → its row at 32 s
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    if (f.tracks.sensor[r] == lost && f.tracks.t[r] == 32.0) last_update[f.tracks.track[r]] = r;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t s = f.tracks.sensor[r], track = f.tracks.track[r];
    const double t = f.tracks.t[r];
    if (s != lost || t <= 32.0)
      out.push_back(s, track, t, f.tracks.state_at(r), f.tracks.cov_at(r), f.tracks.truth[r]);
    if (s != lost) continue;
    if (t >= 36.0)
      out.push_back(s, track + kRenumber, t, f.tracks.state_at(r), f.tracks.cov_at(r), f.tracks.truth[r]);
    if (after.count(t) && last_update.count(track)) {
      const std::size_t u = last_update.at(track);
      auto x = f.tracks.state_at(u);
      const double dt = t - 32.0;
      x[0] += x[2] * dt, x[1] += x[3] * dt;
      out.push_back(s, track, t, x, f.tracks.cov_at(u) * after.at(t), f.tracks.truth[r]);
    }
  }
  f.tracks = out;
  return f;
}

// The segment pass with options `so` on a file where it makes no target correct (the overlaps
// refused): its metrics, for segments_make_every_target_correct.
inline AssociationMetrics nothing_correct_with(const TrackFile& f, const SegmentOptions& so) {
  const AssociationMetrics m =
      evaluate_association(f.tracks, f.sensors, associate(f, true, 2.0, {}, so).record);
  EXPECT_GT(m.targets, 3);
  EXPECT_EQ(m.correct, 0)
      << "a successor overlapping its predecessor by > 2 s joins nothing without the rule";
  return m;
}

}  // namespace trackassoc::testing_support
