// Experiment `seed004` (seed 004 §3; issue 6 item 5): the improved CHNN with pseudo-tracks on four
// asynchronous 3-D sensors with unequal track counts.
//
// Cases: the paper's 5 targets (straight, turning and manoeuvring paths; the embedded scenario
// `seed004`) and 25 dense crossing targets (`seed004_25`); their descriptions list every detail
// the paper leaves out. Unequal counts: in every run each sensor loses each target's local track
// with probability p_miss (a coverage gap), so a target may be seen by only some of the sensors.
// Association: the S-D pipeline over all four sensors (engine/pipeline/pipeline_sd.hpp). Solvers:
//   chnn-eq12-single  seed 004's CHNN with pseudo-tracks and the gated distances of Eq. 12, one
//                     pass as in the paper (tracks the reference sensor did not see stay alone);
//   chnn-eq12  the same plus our leftover passes (kernels/hopfield/chnn_pseudo.hpp);
//   chnn-eq7   chnn-eq12 with Eq. 7 only (no gate on real pairs): the convergence baseline;
//   lr+ls      the S-D Lagrangian relaxation with local search (lower bound and gap);
//   exact      branch and bound from lr+ls (proven optimal, or stopped at its time limit).
// The correct association rate of a run is the share of targets whose local tracks (on the
// sensors that kept them) form exactly one tuple (engine/pipeline/metrics.hpp). The table prints the mean
// rate, the mean solve time, the CHNN's Euler steps and its neuron count beside the paper's ≈ 90 %
// in the dense case and its claim that Eq. 12 speeds convergence (its Table 1 was lost).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

struct Seed004ExperimentOptions {
  std::vector<std::string> scenarios{"seed004", "seed004_25"};
  int32_t runs = 10;
  double p_miss = 0.1;  // chance that a sensor has no track of a target
  std::vector<std::string> solvers{"chnn-eq12-single", "chnn-eq12", "chnn-eq7", "lr+ls", "exact"};
  double exact_time_limit_s = 5.0;
  uint64_t seed = 1;
  std::string output = "experiment-seed004.h5";
  std::string plot = "experiment-seed004.svg";
  void validate() const;
};

struct Seed004Row {
  std::string scenario;
  int32_t targets = 0;
  int32_t run = 0;
  std::string solver;
  double correct_rate = 0.0;  // 0..1
  double objective = 0.0;
  double lower_bound = 0.0;  // NaN where none
  double wall_s = 0.0;
  int64_t steps = 0;    // CHNN Euler steps (0 for the others)
  int64_t neurons = 0;  // CHNN stored neurons
  bool converged = false;
};

// Removes every report of a (sensor, target) local track with probability p_miss, deterministic in
// (seed, run). Returns the number of local tracks removed.
int32_t drop_sensor_target_tracks(TrackFile& file, double p_miss, uint64_t seed, int32_t run);

std::vector<Seed004Row> run_seed004_experiment(const Seed004ExperimentOptions& options,
                                               std::ostream* progress);
std::string seed004_summary_table(const std::vector<Seed004Row>& rows,
                                  const Seed004ExperimentOptions& options);
void write_seed004_outputs(const std::vector<Seed004Row>& rows, const Seed004ExperimentOptions& options);

}  // namespace trackassoc
