// Experiment `schedules` (issue 5 item 7; docs/design.md §4.4 "Schedules. Compare them"): every Hopfield
// schedule and both energies, against the strong simple baseline (greedy + LAP local search) and
// the Lagrangian relaxation, on
//   - seed 000 tracking instances: the embedded `seed000` scenario with n = 10, 20, 50, 100
//     random targets (engine/simulation/simulation.hpp, engine/pipeline/pipeline.hpp), reference = the LR
//     lower bound;
//   - DecompLib ap3.n.k instances (benchmarks/3dap/decomplib), reference = the known optimum.
// Per (instance, method): objective, gap to the reference, raw validity rate (before repair),
// mean sweeps per restart, wall time. Output: a text table, an HDF5 file (one 1-D dataset per
// column under /schedules, the method names as an attribute) and an SVG plot of gap vs wall time.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "engine/report/svg_scatter.hpp"  // svg_scatter, used by the studies that include this header
#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

struct SchedulesExperimentOptions {
  std::vector<int32_t> tracking_sizes{10, 20, 50, 100};
  int32_t runs = 3;  // tracking instances per size
  std::vector<int32_t> decomplib_sizes{10, 20, 30, 40};
  int32_t decomplib_per_size = 3;  // ap3.n.1 .. ap3.n.k
  std::string decomplib_dir;       // empty: <shared>/benchmarks/3dap/decomplib is required
  int32_t restarts = 8;
  // Methods to run, by their table names (schedules_method_names()); empty = all of them.
  std::vector<std::string> methods;
  uint64_t seed = 1;
  std::string output = "experiment-schedules.h5";
  std::string plot = "experiment-schedules.svg";
  void validate() const;
};

// One test instance with its reference objective.
struct ReferencedInstance {
  std::string family;  // "tracking" or "decomplib"
  std::string name;
  CostTensor3 cost;
  double reference = 0.0;
  bool reference_is_optimum = false;  // false: a lower bound (LR)
};

struct ScheduleRow {
  std::string family, instance, method;
  int32_t n = 0;
  double objective = 0.0, reference = 0.0, gap = 0.0;
  double raw_validity = -1.0;  // −1: not a network
  double sweeps = 0.0;         // mean per restart (networks), iterations (LR), rounds (LS)
  double wall_s = 0.0;
  bool valid = false;
};

// The names of the compared methods, in table order ("async/full" is the default `hopfield`).
std::vector<std::string> schedules_method_names();

// Seed 000 tracking instances: scenario `seed000` with `n` targets, Monte Carlo run `run`.
ReferencedInstance seed000_tracking_instance(int32_t n, uint64_t seed, int32_t run);

// Every method on every instance; the instances are sharded over the ranks of distributed::world()
// (rank 0 returns the rows of one process, in its order; the others none).
std::vector<ScheduleRow> run_schedules_experiment(const SchedulesExperimentOptions& options,
                                                  std::ostream* progress);

// Aggregated table: per (family, n, method) mean gap, share within 1 %, raw validity, sweeps, time.
std::string schedules_summary_table(const std::vector<ScheduleRow>& rows);

// HDF5 (atomic) and SVG (atomic) outputs.
void write_schedules_outputs(const std::vector<ScheduleRow>& rows, const SchedulesExperimentOptions& options);

}  // namespace trackassoc
