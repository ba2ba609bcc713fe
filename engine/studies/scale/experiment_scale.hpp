// `trackassoc experiment scale` (issue 6): the sparse association path from 10² to 10⁴ (and more)
// targets per sensor at a fixed, realistic density, with time and peak memory per stage
// (alignment, candidates, statistics, components, solve) and the correct association rate; at the
// sizes where the dense path fits, the dense path with the same solver beside it and a check that
// both give the same associations.
//
// Track sets: recorded-track surrogates (synthetic_recorded_tracks), not the full simulation: each
// local track reports truth + a Gaussian error drawn from the covariance it reports, at its
// sensor's own period and offset (asynchronous sensors). This keeps the generator out of the
// timings and makes the statistic's model hold exactly, so that the experiment measures the
// association path alone. The correct rate is engine/pipeline/metrics.hpp's.
//
// Peak memory: each size runs in a child process (fork), so getrusage's ru_maxrss of the child is
// the peak of that size alone; it is read after each stage.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

// Targets at constant velocity in a box (x, y uniform in [0, box], z in [0, box_z] in 3-D),
// horizontal speed uniform in [speed_min, speed_max] with a uniform heading and a small vertical
// rate; S sensors with periods and offsets; per-track diagonal covariance scaled by a factor in
// [0.5, 2]; sensor s sees a target with probability p_seen. Local track numbers are shuffled per
// sensor; /tracks/truth holds the target id. Streams: CounterRng(seed, ...).
struct SyntheticTrackSpec {
  int32_t targets = 100;
  int32_t sensors = 3;
  bool three_d = true;
  double box = 20000.0, box_z = 10000.0;        // [m]
  double speed_min = 150.0, speed_max = 250.0;  // [m/s]
  double vertical_speed = 5.0;                  // σ of the vertical rate [m/s], 3-D only
  bool formation = false;                       // every target takes the first target's velocity
  double duration = 30.0;                       // [s]
  double sigma_pos = 150.0, sigma_vel = 10.0;   // [m], [m/s]
  double p_seen = 1.0;
  // Each local track covers a random sub-interval of at least this fraction of the duration
  // (births and deaths at different times per sensor); 1 = every track covers the whole duration.
  double min_lifetime_fraction = 1.0;
  std::vector<double> periods{1.0, 2.0, 1.5, 2.5, 3.0};
  std::vector<double> offsets{0.0, 0.3, 0.7, 0.2, 0.5};
  uint64_t seed = 1;
  void validate() const;
};

TrackFile synthetic_recorded_tracks(const SyntheticTrackSpec& spec);

struct ScaleExperimentOptions {
  std::vector<int32_t> sizes{100, 300, 1000, 3000, 10000};
  int32_t dense_max = 300;          // also run the dense path up to this n
  std::string solver = "pairwise";  // engine/solvers/solver_registry.hpp, for both paths
  nlohmann::json solver_options = nlohmann::json::object();
  double density =
      100.0;  // targets per 100 km² of ground (seed 003: 10⁴ in 100×100 km): box = √(n / density)·10 km
  SyntheticTrackSpec tracks;  // everything but targets, box and seed
  double gate_probability = 0.999;
  uint64_t seed = 1;
  int threads = 0;      // 0 = all cores
  bool isolate = true;  // fork one child per size (clean peak memory)
  void validate() const;
  // The options as recorded in scale.json and the HDF5 `options` attribute: sizes, dense_max,
  // solver, solver_options, density_per_100km2, gate_probability, duration, sigma_pos, p_seen,
  // min_lifetime_fraction, three_d, seed, threads.
  nlohmann::json to_json() const;
};

struct ScaleRow {
  int32_t n = 0;                // targets
  std::vector<int32_t> tracks;  // tracks per sensor
  int64_t candidate_pairs = 0, gated_pairs = 0;
  int32_t components = 0, largest_component = 0;
  std::vector<std::string> stage;  // alignment, candidates, statistics, components, solve
  std::vector<double> stage_s, stage_peak_mib, stage_data_mib;
  double total_s = 0.0, peak_mib = 0.0;
  double correct_rate = 0.0, false_rate = 0.0, missed_rate = 0.0;
  bool dense_run = false;
  double dense_total_s = 0.0, dense_peak_mib = 0.0, dense_correct_rate = 0.0;
  bool dense_identical = false;   // same tuple set
  int64_t dense_gated_pairs = 0;  // in-gate pairs of the dense statistic (lossless check)
  std::string error;              // non-empty when the size failed (e.g. out of memory)
  nlohmann::json to_json() const;
  static ScaleRow from_json(const nlohmann::json& j);
};

// Runs every size (ascending), calling progress(row) after each.
std::vector<ScaleRow> run_scale_experiment(const ScaleExperimentOptions& options,
                                           const std::function<void(const ScaleRow&)>& progress = {});

// The table printed by the CLI, and the CSV written beside it.
std::string scale_table(const std::vector<ScaleRow>& rows);
std::string scale_csv(const std::vector<ScaleRow>& rows);

// Writes the rows as HDF5, atomically (io/atomic_file.hpp), for h5py / MATLAB:
//   /            attrs format = "trackassoc-experiment", experiment = "scale", created_by,
//                options (JSON text), loglog_slope_n_ge_1000
//   /scale/      one entry per size (K rows, ascending n):
//     n (K int32), tracks (K×3 int32, tracks per sensor), components, largest_component (K int32),
//     candidate_pairs, gated_pairs (K float64, counts; exact below 2^53),
//     stage_s, stage_peak_mib, stage_data_mib (K×5 float64, columns = attr `stages`:
//       alignment, candidates, statistics, components, solve),
//     total_s, peak_mib, correct_rate, false_rate, missed_rate (K float64),
//     dense_run (K int32, 1 = the dense path also ran), dense_total_s, dense_peak_mib,
//     dense_correct_rate, dense_gated_pairs (K float64, NaN where the dense path did not run),
//     dense_identical (K int32: 1 same tuple set, 0 different, −1 not run),
//     ok (K int32, 0 = the size failed); attr errors = JSON array of K strings ("" when ok).
//   Values of a failed size are NaN / 0.
void write_scale_h5(const std::string& path, const std::vector<ScaleRow>& rows, const nlohmann::json& options,
                    double loglog_slope);

// The files of `trackassoc experiment scale --output DIR`, each written atomically: DIR/scale.csv
// (scale_csv), DIR/scale.json ({options, loglog_slope_n_ge_1000, rows}, ScaleRow::to_json) and
// DIR/scale.h5 (write_scale_h5); `dir` must exist.
void write_scale_outputs(const std::string& dir, const std::vector<ScaleRow>& rows,
                         const ScaleExperimentOptions& options, double loglog_slope);

// Least-squares slope of log(total time) against log(n) over rows with n ≥ n_min: ≈1 for
// n log n at these sizes (the log factor adds ≈0.1), 2 for n².
double scaling_exponent(const std::vector<ScaleRow>& rows, int32_t n_min);

}  // namespace trackassoc
