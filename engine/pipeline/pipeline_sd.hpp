// The association pipeline for S ≥ 2 sensors with dummies (docs/design.md §4.3; issue 6 item 2):
//   local tracks → common times → alignment → pairwise statistics λ → S-D cost tensor with a dummy
//   per sensor → S-D solver → tuples (/associations/<name>/).
//
// Sensors, common times and alignment are the front end's (engine/pipeline/front_end.hpp,
// SensorRule::kTwoOrMore: by default the union of
// the report spans and two-sided alignment; PipelineOptions::paper(): the intersection and forward
// prediction); the pair statistics are computed on every pair of tracks.
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
// and chnn-pseudo (seed 004's CHNN with pseudo-tracks, engine/solvers/chnn_pseudo_solver.hpp, on
// sd_problem_view). Every solver's tuples are scored on the same tensor, so objectives compare.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/pipeline/pipeline.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc {

// The front end's S aligned sensors (engine/pipeline/front_end.hpp), their pair statistics on
// every pair (the dense pair source) and the S-D tensor of the whole problem, its one component
// (partition.hpp).
struct SDProblem : AlignedSensors {
  std::vector<PairStatistic> pairs;      // pairs[a·S + b] for a < b
  std::vector<std::vector<float>> link;  // λ − γ per pair entry, +inf outside the gate; same indexing
  std::vector<double> gate;              // γ at the pair's largest dof, per pair slot
  CostTensorSD tensor;
  std::vector<StageReport> stages;  // alignment, statistics, tensor
};

// options.sensors: empty = every sensor of the file, else ≥ 2 ids. Throws InputError on unknown
// ids, fewer than 2 sensors, a gate probability of 1, or a tensor over the memory budget.
SDProblem build_sd_problem(const TrackFile& file, const PipelineOptions& options);

// The S-D solvers: the registry's entries with capabilities.sd (engine/solvers/solver_registry.hpp).
const std::vector<std::string>& sd_solver_names();
// Throws InputError listing the S-D solvers when `name` is not one.
void require_sd_solver(const std::string& name);

// What a whole-problem S-D solver sees of `p` (engine/solvers/solver_registry.hpp); it refers to
// p's pair statistics, gates and tensor, so `p` must outlive it.
SDProblemView sd_problem_view(const SDProblem& p);

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
