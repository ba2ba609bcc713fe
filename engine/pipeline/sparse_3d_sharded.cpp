// The sparse three-sensor components over MPI ranks (engine/pipeline/sparse_3d_sharded.hpp).
#include "engine/pipeline/sparse_3d_sharded.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "engine/distributed/sharding.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

void encode_matrices(distributed::ByteWriter& w, const SparseComponentMatrices& m) {
  w.put(m.tracks);
  w.put(m.n);
  w.put(m.miss_cost);
  w.put<uint8_t>(m.all_pairs);
  w.put(m.c12);
  w.put(m.c23);
  w.put(m.c13);
}

SparseComponentMatrices decode_matrices(distributed::ByteReader& r) {
  SparseComponentMatrices m;
  m.tracks = r.get<std::array<int32_t, 3>>();
  m.n = r.get<std::array<int32_t, 3>>();
  m.miss_cost = r.get<float>();
  m.all_pairs = r.get<uint8_t>() != 0;
  m.c12 = r.get_vector<float>();
  m.c23 = r.get_vector<float>();
  m.c13 = r.get_vector<float>();
  return m;
}

void encode_solution(distributed::ByteWriter& w, const SparseComponentSolution& x) {
  w.put(x.tuples);
  const SolverSummary& s = x.summary;
  w.put<int32_t>(static_cast<int32_t>(s.termination));
  w.put<uint8_t>(s.feasible);
  w.put(s.objective);
  w.put(s.lower_bound);
  w.put(s.gap);
  w.put(s.abs_gap);
  w.put(s.iterations);
  w.put(s.sweeps);
  w.put(s.wall_time_s);
  w.put(s.message);
}

SparseComponentSolution decode_solution(distributed::ByteReader& r) {
  SparseComponentSolution x;
  x.tuples = r.get_vector<Tuple3>();
  SolverSummary& s = x.summary;
  s.termination = static_cast<Termination>(r.get<int32_t>());
  s.feasible = r.get<uint8_t>() != 0;
  s.objective = r.get<double>();
  s.lower_bound = r.get<double>();
  s.gap = r.get<double>();
  s.abs_gap = r.get<double>();
  s.iterations = r.get<int64_t>();
  s.sweeps = r.get<int64_t>();
  s.wall_time_s = r.get<double>();
  s.message = r.get_string();
  return x;
}

}  // namespace

SparseComponentShards plan_sparse_component_shards(const SparseAssociationProblem& p,
                                                   const SparsePipelineOptions& options, int ranks) {
  SparseComponentShards plan;
  (void)sparse_component_work(p, options);  // an oversized component is refused as by one process
  const bool pad = std::isinf(options.miss_cost);
  for (int32_t c = 0; c < p.components.count; ++c) {
    if (p.components.size(c) < 2) continue;
    auto n = component_track_counts(p, c);
    if (pad) n.fill(std::max({n[0], n[1], n[2]}));
    plan.components.push_back(c);
    plan.cost.push_back(static_cast<double>(n[0]) * n[1] * n[2]);
  }
  plan.rank = distributed::balance_by_cost(plan.cost, ranks);
  return plan;
}

std::vector<distributed::Bytes> encode_sparse_component_parts(const SparseAssociationProblem& p,
                                                              const SparseComponentShards& plan, int ranks,
                                                              const std::string& solver,
                                                              const nlohmann::json& solver_options,
                                                              uint64_t seed,
                                                              const SparsePipelineOptions& options) {
  return distributed::encode_planned_parts(
      ranks, plan.rank,
      [&](distributed::ByteWriter& w, uint64_t items) {
        w.put(solver);
        w.put(solver_options.dump());
        w.put<uint64_t>(items);
      },
      [&](std::size_t k, distributed::ByteWriter& out) {  // the matrices, built in parallel
        const int32_t c = plan.components[k];
        out.put<int32_t>(c);
        out.put<uint64_t>(stream_key(seed, static_cast<uint64_t>(c)));
        encode_matrices(out, sparse_component_matrices(p, c, options));
      });
}

distributed::Bytes solve_sparse_component_part(const distributed::Bytes& part, std::string* shard,
                                               const distributed::Communicator* comm) {
  distributed::ByteReader rd(part);
  const std::string solver = rd.get_string();
  const nlohmann::json options = nlohmann::json::parse(rd.get_string());
  const auto n = static_cast<std::size_t>(rd.get<uint64_t>());
  std::vector<int32_t> index(n);
  std::vector<uint64_t> key(n);
  std::vector<SparseComponentMatrices> matrices(n);
  std::size_t part_tracks = 0;
  for (std::size_t k = 0; k < n; ++k) {
    index[k] = rd.get<int32_t>();
    key[k] = rd.get<uint64_t>();
    matrices[k] = decode_matrices(rd);
    for (int32_t t : matrices[k].tracks) part_tracks += t;
  }
  if (shard) *shard = std::to_string(n) + " components (" + std::to_string(part_tracks) + " tracks)";
  if (comm && shard) distributed::inject_fault_for_tests(*comm, *shard);
  const SolverEntry& entry = find_solver(solver);
  std::vector<SparseComponentSolution> results(n);
  distributed::solve_part_items(
      n,
      [&](std::size_t k) {
        Solution3 sol = entry.solve(sparse_component_tensor(matrices[k]), options, key[k]);
        results[k] = {std::move(sol.tuples), sol.summary};
      },
      [&](std::size_t k) {
        const auto& t = matrices[k].tracks;
        return "component " + std::to_string(index[k]) + " (" + std::to_string(t[0] + t[1] + t[2]) +
               " tracks)";
      },
      shard);
  distributed::ByteWriter w;
  for (std::size_t k = 0; k < n; ++k) {
    w.put<int32_t>(index[k]);
    encode_solution(w, results[k]);
  }
  return w.take();
}

std::vector<SparseComponentSolution> merge_sparse_component_results(
    const SparseAssociationProblem& p, const std::vector<distributed::Bytes>& solved) {
  std::vector<SparseComponentSolution> results(p.components.count);
  std::vector<char> have(p.components.count, 0);
  for (const auto& part : solved) {
    distributed::ByteReader rd(part);
    while (!rd.done()) {
      const auto c = rd.get<int32_t>();
      results.at(c) = decode_solution(rd);
      have[c] = 1;
    }
  }
  for (int32_t c = 0; c < p.components.count; ++c)
    if (p.components.size(c) > 1 && !have[c])
      throw std::logic_error("component " + std::to_string(c) + " was solved by no rank (a bug)");
  return results;
}

std::vector<SparseComponentSolution> solve_sparse_components_sharded(
    distributed::Communicator& comm, const SparseAssociationProblem& p, const std::string& solver,
    const nlohmann::json& solver_options, uint64_t seed, const SparsePipelineOptions& options) {
  const int N = comm.size();
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t sent0 = comm.stats().bytes_sent, received0 = comm.stats().bytes_received;
  const SparseComponentShards plan = plan_sparse_component_shards(p, options, N);
  const auto parts = encode_sparse_component_parts(p, plan, N, solver, solver_options, seed, options);
  const double plan_s = seconds_since(t0);
  const distributed::Bytes mine = distributed::scatter_work(comm, parts);
  const uint64_t scattered = comm.stats().bytes_sent - sent0;
  const auto t1 = std::chrono::steady_clock::now();
  const auto solved = distributed::gather_shards(comm, [&](std::string& shard) {
    shard = "its components";
    return solve_sparse_component_part(mine, &shard, &comm);
  });
  const double exchange_s = seconds_since(t1);
  auto results = merge_sparse_component_results(p, solved);
  if (std::getenv("TRACKASSOC_MPI_STATS")) {
    const std::vector<double> share = distributed::cost_share_per_rank(plan.cost, plan.rank, N);
    std::string per_rank;
    for (int r = 0; r < N; ++r) per_rank += (r ? ", " : "") + std::to_string(share[r]);
    std::fprintf(stderr,
                 "mpi: %d ranks, %zu sparse 3-D components of 2+ tracks, share of cost per rank: %s; "
                 "scattered %llu B, gathered %llu B; plan+encode %.3f s, solve+gather %.3f s\n",
                 N, plan.components.size(), per_rank.c_str(), static_cast<unsigned long long>(scattered),
                 static_cast<unsigned long long>(comm.stats().bytes_received - received0), plan_s,
                 exchange_s);
  }
  return results;
}

void serve_sparse_components(distributed::Communicator& comm) {
  const distributed::Bytes mine = distributed::scatter_work(comm, {});
  distributed::gather_shards(comm, [&](std::string& shard) {
    shard = "its components";
    return solve_sparse_component_part(mine, &shard, &comm);
  });
}

}  // namespace trackassoc
