// The sparse association pipeline for three sensors (docs/design.md §4.3, "Sparse form"): the path for
// recorded track sets too large for the dense n1·n2·n3 tensor.
//
//   the default path's front half over exactly three sensors (build_sparse_front_half,
//   engine/pipeline/sparse_sd_pipeline.hpp; the same code, stage reports and memory budget):
//     local tracks → sensors, common times, alignment    (the front end, engine/pipeline/front_end.hpp)
//     → the per-scan candidate index, λ on the candidates, the gate
//                                                        (the pair source, engine/pipeline/pair_source.hpp)
//     → connected components of the gated pair graph     (the partition, engine/pipeline/partition.hpp)
//   → per component, in parallel (TBB): a small dense sub-tensor, any registered solver
//   → decoding into the same AssociationRecord as the dense pipeline.
// Under MPI (options.ranks, more than one rank) the components are solved on the ranks and decoded
// on rank 0 (solve_sparse_components_sharded below), with the same record.
//
// The common time grid, the alignment, the statistic, the cost forms, the gated-pair cost and
// the decoding rules are those of engine/pipeline/pipeline.hpp, so that dense and sparse give identical
// associations where both fit (tests/engine/pipeline/test_sparse_pipeline.cpp).
//
// Sub-tensor of a component with n1, n2, n3 tracks of the three sensors:
//  * miss_cost = +inf (default, as the dense tensor): the sub-tensor is padded to N = max(n1, n2, n3)
//    in every dimension with phantom indices. Any pair with a phantom is charged the gated-pair
//    cost G, exactly as a pair of tracks from two different components is charged G in the dense
//    tensor; a phantom is decoded as "no track". So every real track is assigned, and the solver
//    sees the same costs as the dense one inside the component.
//  * finite miss_cost: no padding; the sub-tensor carries the miss cost and the solver uses the
//    dummy index (kNoTrack) of kernels/assignment/assignment_types.hpp. The solvers return complete tuples
//    only, so the tracks they leave unassigned are then paired greedily by ascending gated-in λ
//    (a target seen by two of the three sensors is still grouped).
// G: options.pipeline.cost.gated_pair_cost, or when 0 the dense rule (10 × the largest in-gate λ of
// the matrices the cost form uses, at least 1e3), computed over the whole problem, not per component.
//
// Components whose sub-tensor exceeds `max_component_entries` are refused with an InputError
// (no sparse-capable 3-D solver is registered); the message gives the component size and the fixes
// (a tighter gate, or a larger limit: AssociatorOptions::max_component_entries).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "engine/distributed/codec.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "io/track_file.hpp"
#include "kernels/assignment/clusters.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

struct SparsePipelineOptions {
  PipelineOptions pipeline;   // sensors, common period, alignment, statistic (gate), cost form, G
  double radius_scale = 1.0;  // CandidateOptions::radius_scale
  float miss_cost = std::numeric_limits<float>::infinity();  // see the header comment
  std::size_t max_component_entries = std::size_t{1} << 24;  // 64 MiB of floats per sub-tensor
  // The MPI ranks that share the components (rank 0's call with a registered solver name; the
  // others run serve_sparse_components, below). Null: this process.
  distributed::Communicator* ranks = nullptr;
  void validate() const;
  nlohmann::json to_json() const;
};

// The front end's three aligned sensors (engine/pipeline/front_end.hpp; node of (sensor d, track
// i) = offset[d] + i), the gated pairs of the candidate index, and their connected components.
struct SparseAssociationProblem : AlignedSensors {
  std::array<std::size_t, 3> candidate_pairs{};  // index output before the gate: 12, 23, 13
  SparsePairStatistic s12, s23, s13;             // in-gate pairs only
  Components components;
  double gated_pair_cost = 0.0;     // G used in every sub-tensor
  std::vector<StageReport> stages;  // alignment, candidates, statistics, components
};

SparseAssociationProblem build_sparse_association_problem(const TrackFile& file,
                                                          const SparsePipelineOptions& options);

// Solves every component with `solver` (engine/solvers/solver_registry.hpp) in parallel and decodes.
// The solver of component c gets the seed stream_key(seed, c). Appends a "solve" StageReport to
// `stages` when given.
AssociationRecord solve_sparse_association(const SparseAssociationProblem& problem, const std::string& solver,
                                           const nlohmann::json& solver_options, uint64_t seed,
                                           const SparsePipelineOptions& options,
                                           std::vector<StageReport>* stages = nullptr);

// The record's tuples as a set, row order aside: what "identical associations" of the sparse and
// the dense path means (tests/engine/pipeline/test_sparse_pipeline.cpp; experiment scale's
// dense_identical, engine/studies/scale/experiment_scale.hpp).
std::set<std::vector<int32_t>> tuple_set(const AssociationRecord& record);

// The same with any solver callable (a custom or test solver): `solve(tensor, seed)`. `name` goes
// to the record's solver attribute.
using ComponentSolver = std::function<Solution3(const CostTensor3&, uint64_t seed)>;
AssociationRecord solve_sparse_association(const SparseAssociationProblem& problem,
                                           const ComponentSolver& solve, const std::string& name,
                                           uint64_t seed, const SparsePipelineOptions& options,
                                           std::vector<StageReport>* stages = nullptr);

// The pieces of the solve, shared with the sharded form (solve_sparse_components_sharded below).
// Component c as a self-contained sub-problem: the pair cost matrices (float(λ) in the gate,
// float(G) otherwise and for phantoms; c13 only for the all-pairs cost), row-major over the local
// indices, n the sub-tensor's dimensions (padded with phantoms when miss_cost = +inf). Throws the
// InputError of an oversized component.
struct SparseComponentMatrices {
  std::array<int32_t, 3> tracks{};  // real tracks of each sensor
  std::array<int32_t, 3> n{};       // sub-tensor dimensions
  float miss_cost = std::numeric_limits<float>::infinity();
  bool all_pairs = true;  // the cost form: b = c12 + c23 + c13, else c12 + c23
  std::vector<float> c12, c23, c13;
};
SparseComponentMatrices sparse_component_matrices(const SparseAssociationProblem& p, int32_t c,
                                                  const SparsePipelineOptions& options);
// The sub-tensor: the pair costs summed in float as the dense tensor does (bit-identical costs).
CostTensor3 sparse_component_tensor(const SparseComponentMatrices& m);
// The components of two or more tracks, largest first; throws the InputError of the first
// oversized one (in that order) before any work.
std::vector<int32_t> sparse_component_work(const SparseAssociationProblem& p,
                                           const SparsePipelineOptions& options);
// The solver's answer for one component: tuples of local indices and its summary.
struct SparseComponentSolution {
  std::vector<Tuple3> tuples;
  SolverSummary summary;
};
// Decodes the solutions (indexed by component; those of one-track components unused) into the
// record exactly as solve_sparse_association does; runtime_s counts from t0.
AssociationRecord sparse_record_from_solutions(const SparseAssociationProblem& p,
                                               const std::vector<SparseComponentSolution>& solutions,
                                               const std::string& solver, uint64_t seed,
                                               const SparsePipelineOptions& options,
                                               std::chrono::steady_clock::time_point t0,
                                               std::vector<StageReport>* stages = nullptr);

// The components of two or more tracks and their estimated cost, the entries of their dense
// sub-tensor (padded when miss_cost = +inf), ascending; throws the InputError of an oversized one,
// as one process does.
struct SparseComponentCosts {
  std::vector<int64_t> component;
  std::vector<double> cost;
};
SparseComponentCosts sparse_component_costs(const SparseAssociationProblem& p,
                                            const SparsePipelineOptions& options);
// Rank 0: the components of two or more tracks over the ranks of `comm` (docs/design.md §8;
// engine/distributed/shard_items.hpp), dealt by sparse_component_costs. Each rank gets per component
// its pair cost matrices and seed key stream_key(seed, c), rebuilds the sub-tensor with the same
// float arithmetic (sparse_component_tensor) and solves it; the solutions (indexed by component)
// are those of one process, to decode with sparse_record_from_solutions. The other ranks run
// serve_sparse_components at the same time.
std::vector<SparseComponentSolution> solve_sparse_components_sharded(
    distributed::Communicator& comm, const SparseAssociationProblem& p, const std::string& solver,
    const nlohmann::json& solver_options, uint64_t seed, const SparsePipelineOptions& options);
void serve_sparse_components(distributed::Communicator& comm);

// How a component and its solution travel (engine/distributed/codec.hpp).
constexpr auto wire_codec(std::type_identity<SparseComponentMatrices>) {
  return distributed::codec<SparseComponentMatrices>(
      "sparse 3-D component", &SparseComponentMatrices::tracks, &SparseComponentMatrices::n,
      &SparseComponentMatrices::miss_cost, &SparseComponentMatrices::all_pairs, &SparseComponentMatrices::c12,
      &SparseComponentMatrices::c23, &SparseComponentMatrices::c13);
}
constexpr auto wire_codec(std::type_identity<SolverSummary>) {
  return distributed::codec<SolverSummary>(
      "solver summary", &SolverSummary::termination, &SolverSummary::feasible, &SolverSummary::objective,
      &SolverSummary::lower_bound, &SolverSummary::gap, &SolverSummary::abs_gap, &SolverSummary::iterations,
      &SolverSummary::sweeps, &SolverSummary::wall_time_s, &SolverSummary::message);
}
constexpr auto wire_codec(std::type_identity<SparseComponentSolution>) {
  return distributed::codec<SparseComponentSolution>(
      "sparse 3-D component solution", &SparseComponentSolution::tuples, &SparseComponentSolution::summary);
}

// Component sizes: counts[d] = tracks of sensor d in component c.
std::array<int32_t, 3> component_track_counts(const SparseAssociationProblem& p, int32_t c);

}  // namespace trackassoc
