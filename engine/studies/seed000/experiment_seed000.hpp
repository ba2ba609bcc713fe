// Experiment `seed000` (seed 000 §4; issue 5 item 8): the paper's Monte Carlo.
//
// Three 2-D radars at (125,125), (235,130), (200,140) km, σρ = 170 m, σθ = 1°, Kalman local
// tracks (the embedded scenario `seed000`, whose description lists the details the paper leaves
// out); 10 and 20 targets; independent and correlated errors; 30 runs. Association by the chain
// cost b_ijk = λ_ij + λ_jk (Eq. 3) solved by hopfield-paper, hopfield, chnn, lr and exact. The
// correct association rate of a run is the share of targets whose three local tracks form one
// output tuple; printed beside the paper's figures (89 / 85 % for 10 targets, 80 / 76 % for 20,
// Hopfield ≈ 6 points above relaxation).
//
// Errors (the paper's "节点间误差相关和误差独立两种情况"). The local estimation errors of two sensors
// that track one target are correlated through the target's process noise, which both Kalman
// filters see (Bar-Shalom 1981). So the two cases differ in the data, as in the paper, and the
// correlated case is the harder one:
//  * independent: the targets move at constant velocity (no process noise), so each track's error
//    comes from its own radar's noise only; association by the independent statistic (Eq. 1–2).
//  * correlated: the targets move with white-noise acceleration σ_a (`process_noise`, the
//    scenario's 2 m/s², which the local filters also assume); association by the correlated
//    statistic with the Bar-Shalom–Campo cross-covariance computed from common process noise
//    (kernels/statistics/cross_covariance.hpp), C = P_a + P_b − P_ab − P_ba.
//
// Cost forms (docs/design.md §4.3). With the paper's chain cost b_ijk = λ_ij + λ_jk (Eq. 3) the 3-D problem
// separates into two independent 2-D assignments (1–2 and 2–3), so every exact solver gives the
// same tuples and a 3-D solver can only lose to the two LAPs; with the all-pairs cost
// λ_ij + λ_jk + λ_ik the 3-D structure is real. Both are run.
//
// Scoring: each solver's tuples are decoded exactly as `associate` decodes them
// (engine/pipeline/pipeline.hpp, solve_association) and scored by `evaluate`'s function
// (engine/pipeline/metrics.hpp), so a study row equals `simulate` + `associate` + `evaluate` on the same
// seeds (tests/engine/studies/test_hopfield_experiments.cpp). Scoring the raw solver tuples would count ties
// between equally costly out-of-gate tuples, won by chance, as correct.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "io/track_file.hpp"
#include "kernels/core/scenario.hpp"

namespace trackassoc {

struct Seed000ExperimentOptions {
  std::vector<int32_t> targets{10, 20};
  int32_t runs = 30;
  double process_noise = 2.0;  // σ_a [m/s²] of the targets in the correlated case (the scenario's)
  std::vector<std::string> forms{"chain", "all-pairs"};
  std::vector<std::string> solvers{"hopfield-paper", "hopfield", "chnn", "lr", "exact"};
  uint64_t seed = 1;
  std::string output = "experiment-seed000.h5";
  std::string plot = "experiment-seed000.svg";
  void validate() const;
};

struct Seed000Row {
  int32_t targets = 0;
  bool correlated = false;
  std::string form;  // chain or all-pairs
  int32_t run = 0;
  std::string solver;
  double correct_rate = 0.0;  // 0..1, evaluate_association on the decoded tuples
  double false_rate = 0.0;    // 0..1
  double objective = 0.0;
  double wall_s = 0.0;
};

// The scenario and the pipeline options of one configuration (exposed for the CLI equivalence
// test): the embedded `seed000` scenario with `targets` targets, and, for the correlated case,
// process noise σ_a on the targets and the Bar-Shalom–Campo statistic.
Scenario seed000_scenario(const Seed000ExperimentOptions& options, int32_t targets, bool correlated);
PipelineOptions seed000_pipeline(const Seed000ExperimentOptions& options, bool correlated,
                                 const std::string& form);

// Over the process's ranks (engine/distributed/communicator.hpp, world()): the rows on rank 0,
// in the order of one process, and none on the other ranks.
std::vector<Seed000Row> run_seed000_experiment(const Seed000ExperimentOptions& options,
                                               std::ostream* progress);
std::vector<Seed000Row> run_seed000_experiment(const Seed000ExperimentOptions& options,
                                               std::ostream* progress, distributed::Communicator& ranks);
std::string seed000_summary_table(const std::vector<Seed000Row>& rows,
                                  const Seed000ExperimentOptions& options);
void write_seed000_outputs(const std::vector<Seed000Row>& rows, const Seed000ExperimentOptions& options);

}  // namespace trackassoc
