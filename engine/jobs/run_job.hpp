// The main job of `trackassoc run`: simulate a scenario, associate its local tracks with the
// default pipeline (every sensor, sparse S-D, calibrated gate), the same with the exact solver and
// with seed 000's gate (chi-square sum, forward alignment at σ = 1 m/s²), and every 3-D solver that
// suits the size on the three-sensor tensor (dense, or sparse with `sparse`), all through the
// association interface (engine/pipeline/associator.hpp); evaluate each (engine/pipeline/metrics.hpp) and
// write trackassoc-run.h5 and two pictures (engine/report/): the recording as a map with the
// default pipeline's association, and a summary chart of every row.
//
// Default scenario: `recorded_formation`, a realistic recording of the family of
// engine/studies/recorded/experiment_recorded.hpp (asynchronous radars, partial and false tracks, turns, and
// targets flying in groups of three 400 m apart, where the gates and the solvers differ).
// Without `solvers`, the 3-D solvers are those whose registry entry's max_default_n is at least
// the largest track count (the largest component's, when sparse).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "io/track_file.hpp"

namespace trackassoc {

struct RunJobOptions {
  std::string scenario = "recorded_formation";  // scenario JSON file or embedded name
  uint64_t seed = 1;
  PipelineOptions pipeline;  // of the default pipeline and the 3-D solvers (sensors, gate, ...)
  bool sparse = false;       // the 3-D solvers on the sparse three-sensor path
  // Rows: default, default-exact, default-chi2-gate (the default pipeline) or 3-D solver names;
  // empty = the three default rows and every 3-D solver that suits the size.
  std::vector<std::string> solvers;
  // Per-solver options keyed by 3-D solver name, e.g. {"hopfield": {"restarts": 8}}.
  nlohmann::json solver_options = nlohmann::json::object();
  // Throws InputError naming the field: an unknown row name, a key of solver_options that names no
  // solver or is not an object, bad pipeline options.
  void validate() const;
};

// run's --options before anything is merged into them: validate()'s checks, plus a solver with
// options that `solvers` leaves out, and a key of a solver's own options that the solver does not
// read (found by solving the 1×1×1 instance with them: every solver parses its options first).
void check_run_solver_options(const nlohmann::json& solver_options, const std::vector<std::string>& solvers);

struct RunRow {
  std::string name;  // the /associations and /metrics group
  AssociationMetrics metrics;
  // The association's summary; its runtime_s is statistics + cost + solve (the 3-D rows share one
  // problem, whose build time is added to each).
  AssociationSummary summary;
};

struct RunJobResult {
  std::string scenario_name;
  TrackFile file;                // the simulation, then every row's association and metrics
  std::size_t local_tracks = 0;  // distinct (sensor, track) of the simulation
  bool three_d_skipped = false;  // 3-D solvers were due but the file has not three sensors
  std::vector<RunRow> rows;      // in run order: the default rows, then the registry's order
};

// Runs the job. `on_scene`, when given, is called once the scene is simulated, before any
// association (with rows empty).
RunJobResult run_main_job(const RunJobOptions& options,
                          const std::function<void(const RunJobResult&)>& on_scene = {});

// Writes the HDF5 file (atomically) and, unless `plot` is empty, the map of the first row's
// association (the default pipeline's) at `plot` and the summary chart beside it
// (run_summary_path), as PNG, or as SVG when `svg` or `plot` ends in .svg.
void write_run_outputs(const RunJobResult& result, const std::string& output, const std::string& plot,
                       bool svg = false);
// The summary chart's path beside the map's: "trackassoc-run.png" -> "trackassoc-run-summary.png".
std::string run_summary_path(const std::string& plot);

}  // namespace trackassoc
