// The association pipeline for S ≥ 2 sensors with dummies (docs/design.md §4.3; issue 6 item 2):
//   local tracks → common times → alignment → pairwise statistics λ → S-D cost tensor with a dummy
//   per sensor → S-D solver → tuples (/associations/<name>/).
//
// Sensors, common times and alignment are the front end's (engine/pipeline/front_end.hpp,
// SensorRule::kTwoOrMore); the pair statistics are computed on every pair of tracks.
//
// Cost of a tuple (engine/pipeline/tuple_cost.hpp, the rule of the default path too): Σ over its
// linked pairs (consecutive members, chain form, seed 000 Eq. 3 in S dimensions, a dummy skipped;
// or every pair, all-pairs form) of the link cost (λ_ab − G(n_ab))/f of SequentialGate, ≤ 0 inside
// the gate; +∞ (forbidden) when two members coexist and fail the gate or the members are not
// connected through gated-in pairs; a pair that never coexists carries no evidence either way. A
// tuple of one track costs 0. So the gate is the cost of not linking two tracks: a link pays off
// when its λ is below the gate (the generalised-likelihood-ratio cost of the S-D assignment
// literature, with the gate as the miss cost). A target seen by 3 of 4 sensors is grouped as
// (i, j, k, dummy). The gate probability must be below 1.
//
// Solvers (sd_solver_names()): lr, lr+ls (kernels/assignment/sd/lagrangian_sd.hpp, options as for the 3-D
// lr), exact (kernels/assignment/sd/assignment_sd.hpp; options time_limit_s, max_nodes; started from lr+ls),
// and chnn-pseudo (seed 004's CHNN with pseudo-tracks, kernels/hopfield/chnn_pseudo.hpp; options A, B, C, D,
// dt, tau, u0, max_steps, tolerance, noise, leftover_passes (−1 = S − 2, 0 = the paper's single pass), gated
// (Eq. 12, default true), lambda_margin (λ = (1 + margin)·γ, default 0.1), and reference (a sensor position;
// default: the sensor with the most tracks)). Every solver's tuples are scored on the same tensor, so
// objectives compare.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/pipeline/pipeline.hpp"
#include "engine/solvers/option_fields.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"
#include "kernels/hopfield/chnn_pseudo.hpp"

namespace trackassoc {

// The front end's S aligned sensors (engine/pipeline/front_end.hpp), their pair statistics on
// every pair (the dense pair source) and the S-D tensor.
struct SDProblem : AlignedSensors {
  std::vector<PairStatistic> pairs;      // pairs[a·S + b] for a < b
  std::vector<std::vector<float>> link;  // λ − γ per pair entry, +inf outside the gate; same indexing
  std::vector<double> gate;              // γ at the pair's largest dof, per pair slot
  CostTensorSD tensor;
  double statistics_time_s = 0.0, tensor_time_s = 0.0;
};

// options.sensors: empty = every sensor of the file, else ≥ 2 ids. Throws InputError on unknown
// ids, fewer than 2 sensors, a gate probability of 1, or a tensor over the memory budget.
SDProblem build_sd_problem(const TrackFile& file, const PipelineOptions& options);

// The S-D solvers: the registry's entries with capabilities.sd (engine/solvers/solver_registry.hpp).
const std::vector<std::string>& sd_solver_names();
// Throws InputError listing the S-D solvers when `name` is not one.
void require_sd_solver(const std::string& name);

// Seed 004's inputs from the problem: distances λ (gated: +inf outside the gate, Eq. 12), and
// pseudo-track costs (1 + margin)·γ; sensors reordered so that `reference` comes first.
PseudoTrackInput pseudo_track_input(const SDProblem& p, bool gated, double lambda_margin, int32_t reference);

// The options of chnn-pseudo (header comment): the network's, and how its inputs are built.
struct ChnnPseudoSolverOptions {
  ChnnPseudoOptions network;  // seed: the run's seed, not an option
  bool gated = true;
  double lambda_margin = 0.1;
  int32_t reference = 0;  // solve_chnn_sd's default: the sensor with the most tracks
};
const OptionFields<ChnnPseudoSolverOptions>& chnn_pseudo_option_fields();

// The chnn-pseudo solver alone; `raw`, when given, receives the network's own result (neurons,
// Euler steps, convergence).
SolutionSD solve_chnn_sd(const SDProblem& p, const nlohmann::json& options, uint64_t seed,
                         ChnnPseudoResult* raw = nullptr);

// Runs a tensor S-D solver (capabilities.sd_tensor: lr, lr+ls, exact) on `tensor` alone; throws
// InputError for others.
SolutionSD solve_sd_tensor(const CostTensorSD& tensor, const std::string& solver,
                           const nlohmann::json& options);

// Runs an S-D solver and returns the solution over the problem's tensor (tuples in tensor order).
SolutionSD solve_sd(const SDProblem& p, const std::string& solver, const nlohmann::json& options,
                    uint64_t seed);

// The tuples of `sol` as output rows (local track numbers in /sensors columns) with their costs,
// appended to rec.tuples and rec.cost; sets rec.num_sensors.
void append_tuples(const SDProblem& p, const SolutionSD& sol, AssociationRecord& rec);

// solve_sd, then the record for /associations/<name>/ (every local track in exactly one tuple).
AssociationRecord solve_sd_association(const SDProblem& p, const std::string& solver,
                                       const nlohmann::json& solver_options, uint64_t seed,
                                       const PipelineOptions& options);

}  // namespace trackassoc
