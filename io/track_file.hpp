// HDF5 track files, schema v1 (docs/design.md §3). Readable with h5py without knowing C++.
//
//   /                      attrs format="trackassoc", schema_version=1, created_by, scenario (JSON text)
//   /sensors/              id, position (S×3), sigma_range, sigma_bearing, sigma_elevation, period,
//                          offset, p_detect, reliability
//   /truth/                target, t, state (N×D)                         optional
//   /measurements/         sensor, t, range, bearing, elevation, target   optional
//   /tracks/               sensor, track, t, state (N×D), cov (N×D(D+1)/2), truth; attr state_layout;
//                          optional attrs frame, frame_origin_{lat_deg,lon_deg,alt_m}, import (RecordingInfo)
//   /associations/<name>/  tuples (K×S int32), cost (K); attrs solver, options, objective,
//                          lower_bound, gap, runtime_s, seed; optional energy (R×T float32);
//                          optional restarts/ (one row per restart: restart, valid_raw, sweeps,
//                          mean_field_steps (int32), energy, repaired_objective, objective (float64))
//   /metrics/<name>/       attrs correct_rate, false_rate, missed_rate; small tables as datasets
//   /system_tracks/<name>/ track, t, state (N×4), mapping/{sensor, local_track, system_track, packets};
//                          attrs method, options (seed 001 fusion centres, io/system_tracks_file.hpp)
//   /fused/<name>/         tuples (K×S), tuple, t, state (N×D), cov (N×D(D+1)/2), sources, truth, omega
//                          (ci); attrs association, rule, ci_criterion, cross_covariance, options,
//                          state_layout (fused tracks of an association, io/fused_tracks_file.hpp)
//   /registration/         sensor, <parameter>, <parameter>_se (S), covariance_scale, pair_observations
//                          (S×S); attrs reference_sensor, parameters, applied, ... (the sensor
//                          registration of the default association, io/registration_file.hpp)
//   /tracks/source_track   optional (N int32): the recorded track number of rows whose track was
//                          split (engine/pipeline/track_hygiene.hpp)
//
// Only /sensors and /tracks are required. The reader validates format, version, shapes, dtypes,
// finiteness and positive-definite covariances, and throws InputError naming file, dataset and row.
// The writer is atomic: it writes PATH.tmp beside PATH, then renames.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/fused_tracks_file.hpp"
#include "io/registration_file.hpp"
#include "io/system_tracks_file.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

struct AssociationRecord {
  std::string name;             // group name under /associations
  int32_t num_sensors = 0;      // S, the number of tuple columns
  std::vector<int32_t> tuples;  // K×S row-major; column s = local track number of sensor s, -1 = none
  std::vector<double> cost;     // K, cost of each tuple
  std::string solver;
  std::string options_json = "{}";
  double objective = 0.0;
  double lower_bound = std::numeric_limits<double>::quiet_NaN();
  double gap = std::numeric_limits<double>::quiet_NaN();
  double runtime_s = 0.0;
  uint64_t seed = 0;
  std::string termination;
  // Optional energy trace, R restarts × T sweeps, row-major; empty when not recorded.
  int32_t energy_rows = 0, energy_cols = 0;
  std::vector<float> energy;
  RestartTable
      restarts;  // optional per-restart table (kernels/assignment/assignment_types.hpp); empty = none
  // Optional U×2 row-major (sensor id, track): the local tracks of the associated sensors in no
  // tuple of two or more members (engine/pipeline/associator.hpp); empty = not recorded.
  std::vector<int32_t> unassociated;
  // Optional K target numbers (≥ 0), one per tuple: tuples of one number are one target followed
  // over time by several local tracks on a sensor (track segments, engine/pipeline/track_segments.hpp);
  // a track never appears in the tuples of two targets. Empty = every tuple is its own target.
  std::vector<int32_t> target;
  std::size_t num_tuples() const { return num_sensors ? tuples.size() / num_sensors : 0; }
};

struct MetricsRecord {
  std::string name;
  double correct_rate = 0.0, false_rate = 0.0, missed_rate = 0.0;
  std::map<std::string, std::vector<double>> tables;  // small 1-D tables, one dataset each
};

// Optional attributes of a recorded track set (set by `trackassoc import csv`, io/csv_tracks.hpp).
// Written only when set, so a simulated file is unchanged; the reader accepts files with and
// without them.
struct RecordingInfo {
  // /tracks attr frame: the frame of the state columns, "ENU" = east, north, up [m] of the local
  // tangent plane at frame_origin; "" = not stated (the positions are as the source gave them).
  std::string frame;
  // /tracks attrs frame_origin_lat_deg, frame_origin_lon_deg, frame_origin_alt_m (WGS-84).
  std::optional<std::array<double, 3>> frame_origin;
  // /tracks attr import: JSON text saying how the rows were made (source, velocity, covariance,
  // the σ assumed per sensor, the periods); "" = none.
  std::string import_json;
  // /sensors attr unknown: the /sensors datasets that hold placeholders, not known values
  // (comma-separated, e.g. "position,sigma_range"); "" = none.
  std::string sensors_unknown;
  friend bool operator==(const RecordingInfo&, const RecordingInfo&) = default;
};

struct TrackFile {
  std::string created_by = "trackassoc 0.1.0";
  std::string scenario_json;  // empty when the file is a recorded track set
  std::vector<Sensor> sensors;
  std::optional<TruthTable> truth;
  std::optional<Measurements> measurements;
  TrackTable tracks;
  std::vector<AssociationRecord> associations;
  std::vector<MetricsRecord> metrics;
  std::vector<SystemTrackRecord> system_tracks;    // /system_tracks/<name>/ (io/system_tracks_file.hpp)
  std::vector<FusedTrackRecord> fused;             // /fused/<name>/ (io/fused_tracks_file.hpp)
  RecordingInfo recording;                         // optional /tracks and /sensors attributes
  std::optional<RegistrationRecord> registration;  // /registration (io/registration_file.hpp)
  // /tracks/source_track (optional, one per row): the track number as recorded, where a split
  // (engine/pipeline/track_hygiene.hpp) gave the row's track a new number; empty = none.
  std::vector<int32_t> source_track;
};

// Reads and validates a schema v1 file. Throws InputError on anything malformed.
// The file is first read in a forked child process (io/isolated_run.hpp): libhdf5 1.10 can hang or
// overrun buffers on damaged files, and this turns that into an InputError. The price is a
// second read; read_track_file_in_process skips the guard (for trusted files and the fuzzer).
// `timeout_s` <= 0 means isolated_read_timeout(path): 10 s plus 1 s per 5 MB of file.
TrackFile read_track_file(const std::string& path, double timeout_s = 0.0);
TrackFile read_track_file_in_process(const std::string& path);

// Writes `file` to `path` atomically (PATH.tmp then rename). Throws InputError if the folder is
// not writable; never leaves a partial file at `path`.
void write_track_file(const std::string& path, const TrackFile& file);

// The model probabilities of an IMM filter bank, one row per /tracks row: /tracks/model_prob
// (N×M float64, additive to schema v1) with the attribute /tracks/models naming the M columns
// (comma-separated). `trackassoc filter --filter cs-nn|imm` writes them beside the tracks.
struct TrackModelProbabilities {
  std::vector<double> prob;  // N×M, row-major
  int32_t num_models = 0;    // M
  std::string models;        // e.g. "cs-nn,ca"
};

// As above, with /tracks/model_prob and /tracks/models in the same atomic write (M > 0).
void write_track_file(const std::string& path, const TrackFile& file,
                      const TrackModelProbabilities& model_prob);

}  // namespace trackassoc
