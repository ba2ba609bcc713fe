// The front end of every association path (docs/design.md §1, "Association is one pipeline of
// stages"; §4.3), written once:
//
//   sensors → common time grid → alignment   (→ registration, engine/pipeline/registration_stage.hpp,
//                                              which re-runs the whole association on corrected reports)
//
// and then the pair source (engine/pipeline/pair_source.hpp) computes the pair statistics on it.
// The dense 3-D (pipeline.hpp), dense S-D (pipeline_sd.hpp), sparse 3-D (sparse_pipeline.hpp) and
// sparse S-D (sparse_sd_pipeline.hpp) problems are each an AlignedSensors plus what their pair
// source and solver add.
//
// Sensors (select_sensors): the chosen /sensors ids, by one of two rules —
//   * SensorRule::kThree (the 3-D tensor paths): exactly three; with no --sensors, the first three
//     of a file of exactly three (a file of more needs --sensors: never a silent drop);
//   * SensorRule::kTwoOrMore (the S-D paths): --sensors (≥ 2 ids) or every sensor of the file.
// The common period is PipelineOptions::common_period, or the largest scan period of the chosen.
//
// Grid (common_time_grid): a uniform grid with step `period` over the union of the sensors' report
// intervals (default), or their intersection starting one period after the latest first report
// (PipelineOptions::paper(), seed 000's simulations). Checked against the memory budget first.
//
// Alignment: each sensor's local tracks moved to the grid (align_tracks,
// kernels/statistics/association_statistic.hpp: two-sided, or forward prediction), then each
// track's first and last valid common time (a pair of tracks whose valid intervals never overlap
// was never tested by the gate: no evidence either way, docs/design.md §4.3).
//
// Complexity: selection O(S log S); grid O(R + K) for R report rows and K common times; alignment
// O(S·R log R + N·K·D³) for N local tracks of state dimension D; valid intervals O(N·K).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

struct PipelineOptions;  // engine/pipeline/pipeline.hpp

enum class SensorRule {
  kThree,      // the 3-D tensor paths: exactly three sensors
  kTwoOrMore,  // the S-D paths: any two or more
};

// The chosen sensors: /sensors ids, their columns in /sensors order, and the common period.
struct SensorSelection {
  int32_t file_sensors = 0;  // columns of the output tuples
  std::vector<int32_t> ids, columns;
  double period = 0.0;
};
// Throws InputError (the messages name the rule's fix) on too few sensors, a wrong count of
// --sensors for kThree, an unknown id, or non-positive periods.
SensorSelection select_sensors(const TrackFile& file, const PipelineOptions& options, SensorRule rule);

// A chosen sensor with no local tracks: refused by common_time_grid (the dense and 3-D paths), or
// left out of the problem with its tuple column −1 (the default path, issue 30).
enum class EmptySensors { kRefuse, kLeaveOut };

// Two tracks' valid common-time intervals [first, last] (first −1: never valid) share a time: the
// pair was tested by the gate (AlignedSensors::coexist, SDComponentView::overlap).
inline bool valid_intervals_meet(int32_t first_a, int32_t last_a, int32_t first_b, int32_t last_b) {
  if (first_a < 0 || first_b < 0) return false;
  return std::max(first_a, first_b) <= std::min(last_a, last_b);
}

// The front end's output: the chosen sensors' tracks aligned to the common times. Local track i of
// sensor position s is node offset[s] + i.
struct AlignedSensors {
  std::vector<int32_t> sensor_ids;        // the chosen sensors with local tracks, in their order
  std::vector<int32_t> empty_sensor_ids;  // EmptySensors::kLeaveOut: the chosen ones without any
  std::vector<int32_t> sensor_columns;    // their columns in /sensors order
  int32_t file_sensors = 0;               // columns of the output tuples
  int32_t dim = 4;                        // state dimension D
  std::vector<double> common_times;
  std::vector<AlignedTracks> aligned;
  std::vector<int32_t> offset;                   // S + 1 entries
  std::vector<int32_t> first_valid, last_valid;  // per node: first and last valid common time (−1: never)

  int32_t S() const { return static_cast<int32_t>(sensor_ids.size()); }
  int32_t nodes() const { return offset.empty() ? 0 : offset.back(); }
  int32_t sensor_of(int32_t node) const {  // the s with offset[s] <= node < offset[s + 1]
    return static_cast<int32_t>(std::upper_bound(offset.begin(), offset.end(), node) - offset.begin()) - 1;
  }
  // Nodes u and v have common valid times, so the gate tested them (a pair that never coexists
  // carries no evidence either way).
  bool coexist(int32_t u, int32_t v) const {
    return valid_intervals_meet(first_valid[u], last_valid[u], first_valid[v], last_valid[v]);
  }
};

// A sensor whose reports the alignment's whiteness test read as independent errors, not a
// filter's output, so their manoeuvre-lag terms were left out (kernels/statistics/report_whiteness.hpp),
// with its ratio (≥ AlignmentOptions::whiteness_threshold; 1 for independent errors).
struct UnfilteredSensor {
  int32_t sensor = 0;
  double whiteness = 0.0;
};
std::vector<UnfilteredSensor> unfiltered_sensors(const AlignedSensors& p);

// The front end: select_sensors(rule), the grid, the alignment and the valid intervals.
AlignedSensors align_sensors(const TrackFile& file, const PipelineOptions& options, SensorRule rule,
                             EmptySensors empty = EmptySensors::kRefuse);

// Common time grid (exposed for tests): see the header comment. Throws InputError when a sensor
// has no local tracks or the sensors never report at a common time.
std::vector<double> common_time_grid(const TrackTable& tracks, std::span<const int32_t> sensor_ids,
                                     double period, bool span_union = false);

}  // namespace trackassoc
