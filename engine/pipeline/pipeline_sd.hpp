// The association pipeline for S ≥ 2 sensors with dummies (docs/design.md §4.3; issue 6 item 2):
//   local tracks → common times → alignment → pairwise statistics λ → S-D cost tensor with a dummy
//   per sensor → S-D solver → tuples (/associations/<name>/).
//
// Common times and alignment are those of the 3-D pipeline (engine/pipeline/pipeline.hpp): a uniform grid
// with step common_period (default: the largest scan period of the chosen sensors), by default over
// the union of the sensors' report spans with each track moved to a grid time from its nearest
// report on either side (two-sided alignment; PipelineOptions::paper(): the intersection, each
// track's latest estimate predicted forward by a CV model).
//
// Cost of a tuple with the set P of real members (in the chosen sensor order):
//   Σ over the links of P of (λ_ab − γ_ab),   γ_ab = χ²-quantile(gate probability, dof_ab),
// the links being consecutive members of P (chain form, seed 000 Eq. 3 in S dimensions; a dummy
// is skipped) or every pair of P (all-pairs form); a link outside the gate makes the tuple +∞
// (forbidden), and a tuple of one track costs 0. So the gate γ is the cost of not linking two
// tracks: a link pays off when its λ is below the gate (the generalised-likelihood-ratio cost of
// the S-D assignment literature, with the chi-square gate as the miss cost). A target seen by 3 of
// 4 sensors is grouped as (i, j, k, dummy). The gate probability must be below 1.
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

struct SDProblem {
  std::vector<int32_t> sensor_ids;      // the chosen sensors, in tensor order
  std::vector<int32_t> sensor_columns;  // their columns in /sensors order
  int32_t file_sensors = 0;             // columns of the output tuples
  std::vector<double> common_times;
  std::vector<AlignedTracks> aligned;
  std::vector<PairStatistic> pairs;      // pairs[a·S + b] for a < b
  std::vector<std::vector<float>> link;  // λ − γ per pair entry, +inf outside the gate; same indexing
  std::vector<double> gate;              // γ at the pair's largest dof, per pair slot
  CostTensorSD tensor;
  double statistics_time_s = 0.0, tensor_time_s = 0.0;
  int32_t S() const { return static_cast<int32_t>(sensor_ids.size()); }
};

// The sensors of an S-D association: options.sensors, or every sensor of the file; their /sensors
// columns; the common-time period (options.common_period, or the largest scan period of them).
// Throws InputError on unknown ids or fewer than 2 sensors. Shared by the dense and sparse S-D.
struct SDSensorSelection {
  std::vector<int32_t> ids, columns;
  double period = 0.0;
};
SDSensorSelection select_sd_sensors(const TrackFile& file, const PipelineOptions& options);

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
