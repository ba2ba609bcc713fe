// The components of the sparse three-sensor pipeline (`associate --sparse`) shared out over MPI
// ranks (docs/design.md §8; issue 19), as engine/pipeline/sparse_sd_sharded.hpp does for the default path.
//
// Rank 0 reads the file and builds the problem (alignment, candidates, gated pair statistics,
// components: engine/pipeline/sparse_pipeline.hpp); a tuple lies in one component, so
//   1. rank 0 plans: every component of two or more tracks gets a rank, balanced by its estimated
//      cost (the entries of its dense sub-tensor), longest first (distributed::balance_by_cost);
//      an oversized component is refused first, as by one process;
//   2. rank 0 scatters each rank its part: the solver, its options and, per component, its index,
//      its seed key stream_key(seed, c) and its pair cost matrices (sparse_component_matrices:
//      c12, c23 and c13 for the all-pairs cost, sizes, miss cost) — O(n1·n2 + n2·n3 [+ n1·n3]);
//   3. every rank (rank 0 too) rebuilds each sub-tensor with the same float arithmetic
//      (sparse_component_tensor), solves its part in parallel (TBB) and returns, per component,
//      the solver's tuples (local indices) and its SolverSummary;
//   4. rank 0 decodes them with its statistics exactly as one process does
//      (sparse_record_from_solutions), so the output is identical for any N.
// Failures follow engine/distributed/sharding.hpp: "rank 1, 12 components (40 tracks): ...", or
// the component that failed.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/distributed/byte_buffer.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"

namespace trackassoc {

// Which rank solves which component (step 1).
struct SparseComponentShards {
  std::vector<int32_t> components;  // the components of two or more tracks, ascending
  std::vector<double> cost;         // their estimated cost (dense sub-tensor entries)
  std::vector<int32_t> rank;        // the rank of each
};
SparseComponentShards plan_sparse_component_shards(const SparseAssociationProblem& p,
                                                   const SparsePipelineOptions& options, int ranks);

// Step 2: one part per rank.
std::vector<distributed::Bytes> encode_sparse_component_parts(const SparseAssociationProblem& p,
                                                              const SparseComponentShards& plan, int ranks,
                                                              const std::string& solver,
                                                              const nlohmann::json& solver_options,
                                                              uint64_t seed,
                                                              const SparsePipelineOptions& options);
// Step 3: a part's components solved. `shard` names the part or, on a failure, the component;
// with `comm`, the test hook of engine/distributed/sharding.hpp may fail the part.
distributed::Bytes solve_sparse_component_part(const distributed::Bytes& part, std::string* shard = nullptr,
                                               const distributed::Communicator* comm = nullptr);
// Step 4: every component's solution (indexed by component) from the parts' results, any order.
std::vector<SparseComponentSolution> merge_sparse_component_results(
    const SparseAssociationProblem& p, const std::vector<distributed::Bytes>& solved);

// Rank 0: steps 1–4 over `comm` (the decoding is sparse_record_from_solutions). The other ranks
// call serve_sparse_components at the same time.
std::vector<SparseComponentSolution> solve_sparse_components_sharded(
    distributed::Communicator& comm, const SparseAssociationProblem& p, const std::string& solver,
    const nlohmann::json& solver_options, uint64_t seed, const SparsePipelineOptions& options);
// Ranks other than 0: receive a part (or rank 0's failure: SilentExit), solve it, send it back.
void serve_sparse_components(distributed::Communicator& comm);

}  // namespace trackassoc
