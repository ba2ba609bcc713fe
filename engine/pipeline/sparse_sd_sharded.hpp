// The components of the sparse S-D pipeline shared out over MPI ranks (docs/design.md §8; issue 19 item 3).
//
// Rank 0 reads the file and builds the problem (alignment, candidates, statistics, components:
// engine/pipeline/sparse_sd_pipeline.hpp); the components are independent S-D problems (a tuple
// lies in one component), so
//   1. rank 0 plans: every component of two or more tracks gets a rank, balanced by its estimated
//      cost (sd_component_cost: dense sub-tensor entries, or the LAP sizes of the merging
//      fallback), longest first (distributed::balance_by_cost); components of one track stay on
//      rank 0, being their own tuple;
//   2. rank 0 scatters each rank its part: the solver, its options, the cost form, the tensor
//      limit and, per component, its index and its self-contained view (tracks, link costs,
//      valid spans; engine/pipeline/sparse_sd_components.hpp) — O(Σ n_a·n_b) per component;
//   3. every rank (rank 0 too) solves its part in parallel (TBB) and returns, per component, the
//      tuples as problem nodes with their costs, objective and bound;
//   4. rank 0 puts the results back by component index and builds the record exactly as one
//      process does (tuples sorted by their nodes), so the output is identical for any N.
// The solvers of the components (lr+ls, lr, exact) are deterministic and get no rank-dependent
// input. Failures follow engine/distributed/sharding.hpp: a rank's failure names its rank and
// component ("rank 1, component 17 (12 tracks): ...").
//
// Diagnostics: with TRACKASSOC_MPI_STATS set, rank 0 prints one line on stderr per sharded
// solve: components per rank, their estimated cost, bytes scattered and gathered, and the times.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/distributed/byte_buffer.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/sparse_sd_components.hpp"

namespace trackassoc {

// Which rank solves which component (step 1).
struct ComponentShards {
  std::vector<int32_t> components;  // the components of two or more tracks, ascending
  std::vector<double> cost;         // their estimated cost (sd_component_cost)
  std::vector<int32_t> rank;        // the rank of each
};
ComponentShards plan_component_shards(const SparseSDProblem& p, std::size_t max_entries, int ranks);

// Step 2: one part per rank.
std::vector<distributed::Bytes> encode_component_parts(const SparseSDProblem& p, const ComponentShards& plan,
                                                       int ranks, const std::string& solver,
                                                       const nlohmann::json& solver_options, bool all_pairs,
                                                       std::size_t max_entries);
// Step 3: a part's components solved, (component, result) each. `shard` names the part ("617
// components (2431 tracks)") or, on a failure, the component (for the error message); with
// `comm`, the test hook of engine/distributed/sharding.hpp may fail the part.
distributed::Bytes solve_component_part(const distributed::Bytes& part, std::string* shard = nullptr,
                                        const distributed::Communicator* comm = nullptr);
// Step 4: every component's result, from the parts' results (any order) and the one-track
// components of `p`.
std::vector<SDComponentResult> merge_component_results(const SparseSDProblem& p,
                                                       const std::vector<distributed::Bytes>& solved);

// Rank 0: steps 1–4 over `comm`. The other ranks call serve_sd_components at the same time.
std::vector<SDComponentResult> solve_sd_components_sharded(distributed::Communicator& comm,
                                                           const SparseSDProblem& p,
                                                           const std::string& solver,
                                                           const nlohmann::json& solver_options,
                                                           bool all_pairs, std::size_t max_entries);
// Ranks other than 0: receive a part (or rank 0's failure: SilentExit), solve it, send it back.
void serve_sd_components(distributed::Communicator& comm);

}  // namespace trackassoc
