// The sparse S-D components over MPI ranks (engine/pipeline/sparse_sd_sharded.hpp).
#include "engine/pipeline/sparse_sd_sharded.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "engine/distributed/sharding.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

ComponentShards plan_component_shards(const SparseSDProblem& p, std::size_t max_entries, int ranks) {
  ComponentShards plan;
  const int32_t S = p.S();
  std::vector<int32_t> n(S);
  for (int32_t c = 0; c < p.components.count; ++c) {
    if (p.components.size(c) < 2) continue;
    SDComponentView counts;  // only the track counts, for the estimate
    counts.S = S;
    counts.tracks.assign(S, {});
    for (int32_t u : p.components.members(c)) counts.tracks[p.sensor_of(u)].push_back(0);
    plan.components.push_back(c);
    plan.cost.push_back(sd_component_cost(counts, max_entries));
  }
  plan.rank = distributed::balance_by_cost(plan.cost, ranks);
  return plan;
}

std::vector<distributed::Bytes> encode_component_parts(const SparseSDProblem& p, const ComponentShards& plan,
                                                       int ranks, const std::string& solver,
                                                       const nlohmann::json& solver_options, bool all_pairs,
                                                       std::size_t max_entries) {
  return distributed::encode_planned_parts(
      ranks, plan.rank,
      [&](distributed::ByteWriter& w, uint64_t items) {
        w.put(solver);
        w.put(solver_options.dump());
        w.put<uint8_t>(all_pairs);
        w.put<uint64_t>(max_entries);
        w.put<uint64_t>(items);
      },
      [&](std::size_t k, distributed::ByteWriter& out) {  // the views, built in parallel
        out.put<int32_t>(plan.components[k]);
        encode_sd_component_view(out, sd_component_view(p, plan.components[k]));
      });
}

distributed::Bytes solve_component_part(const distributed::Bytes& part, std::string* shard,
                                        const distributed::Communicator* comm) {
  distributed::ByteReader rd(part);
  const std::string solver = rd.get_string();
  const nlohmann::json options = nlohmann::json::parse(rd.get_string());
  const bool all_pairs = rd.get<uint8_t>() != 0;
  const auto max_entries = static_cast<std::size_t>(rd.get<uint64_t>());
  const auto n = static_cast<std::size_t>(rd.get<uint64_t>());
  std::vector<int32_t> index(n);
  std::vector<SDComponentView> views(n);
  for (std::size_t k = 0; k < n; ++k) {
    index[k] = rd.get<int32_t>();
    views[k] = decode_sd_component_view(rd);
  }
  std::size_t part_tracks = 0;
  for (const auto& v : views)
    for (const auto& t : v.tracks) part_tracks += t.size();
  if (shard) *shard = std::to_string(n) + " components (" + std::to_string(part_tracks) + " tracks)";
  if (comm && shard) distributed::inject_fault_for_tests(*comm, *shard);
  std::vector<SDComponentResult> results(n);
  distributed::solve_part_items(
      n,
      [&](std::size_t k) {
        results[k] = solve_sd_component(views[k], solver, options, all_pairs, max_entries);
      },
      [&](std::size_t k) {
        std::size_t tracks = 0;
        for (const auto& t : views[k].tracks) tracks += t.size();
        return "component " + std::to_string(index[k]) + " (" + std::to_string(tracks) + " tracks)";
      },
      shard);
  distributed::ByteWriter w;
  for (std::size_t k = 0; k < n; ++k) {
    w.put<int32_t>(index[k]);
    encode_sd_component_result(w, results[k]);
  }
  return w.take();
}

std::vector<SDComponentResult> merge_component_results(const SparseSDProblem& p,
                                                       const std::vector<distributed::Bytes>& solved) {
  std::vector<SDComponentResult> results(p.components.count);
  std::vector<char> have(p.components.count, 0);
  for (int32_t c = 0; c < p.components.count; ++c)
    if (p.components.size(c) == 1) {
      results[c] = single_track_component(p.components.members(c)[0]);
      have[c] = 1;
    }
  for (const auto& part : solved) {
    distributed::ByteReader rd(part);
    while (!rd.done()) {
      const auto c = rd.get<int32_t>();
      results.at(c) = decode_sd_component_result(rd);
      have[c] = 1;
    }
  }
  for (int32_t c = 0; c < p.components.count; ++c)
    if (!have[c]) throw std::logic_error("component " + std::to_string(c) + " was solved by no rank (a bug)");
  return results;
}

std::vector<SDComponentResult> solve_sd_components_sharded(distributed::Communicator& comm,
                                                           const SparseSDProblem& p,
                                                           const std::string& solver,
                                                           const nlohmann::json& solver_options,
                                                           bool all_pairs, std::size_t max_entries) {
  const int N = comm.size();
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t sent0 = comm.stats().bytes_sent, received0 = comm.stats().bytes_received;
  const ComponentShards plan = plan_component_shards(p, max_entries, N);
  const auto parts = encode_component_parts(p, plan, N, solver, solver_options, all_pairs, max_entries);
  const double plan_s = seconds_since(t0);
  const distributed::Bytes mine = distributed::scatter_work(comm, parts);
  const uint64_t scattered = comm.stats().bytes_sent - sent0;
  const auto t1 = std::chrono::steady_clock::now();
  double solve_s = 0.0;
  const auto solved = distributed::gather_shards(comm, [&](std::string& shard) {
    shard = "its components";
    auto r = solve_component_part(mine, &shard, &comm);
    solve_s = seconds_since(t1);
    return r;
  });
  const double exchange_s = seconds_since(t1);
  auto results = merge_component_results(p, solved);
  if (std::getenv("TRACKASSOC_MPI_STATS")) {
    const std::vector<double> share = distributed::cost_share_per_rank(plan.cost, plan.rank, N);
    std::vector<int> count(N, 0);
    double total = 0.0;
    for (std::size_t k = 0; k < plan.cost.size(); ++k) {
      ++count[plan.rank[k]];
      total += plan.cost[k];
    }
    double largest = 0.0;
    for (double c : plan.cost) largest = std::max(largest, c);
    std::string per_rank;
    for (int r = 0; r < N; ++r)
      per_rank += (r ? ", " : "") + std::to_string(count[r]) + " (" + std::to_string(share[r]) + ")";
    std::fprintf(
        stderr,
        "mpi: %d ranks, %d components (%zu of 2+ tracks; the largest %.3f of the estimated cost), per rank: "
        "components (share of cost): %s; "
        "scattered %llu B, gathered %llu B; plan+encode %.3f s, rank 0 solve %.3f s, solve+gather "
        "%.3f s\n",
        N, p.components.count, plan.components.size(), largest / total, per_rank.c_str(),
        static_cast<unsigned long long>(scattered),
        static_cast<unsigned long long>(comm.stats().bytes_received - received0), plan_s, solve_s,
        exchange_s);
  }
  return results;
}

void serve_sd_components(distributed::Communicator& comm) {
  const distributed::Bytes mine = distributed::scatter_work(comm, {});
  distributed::gather_shards(comm, [&](std::string& shard) {
    shard = "its components";
    return solve_component_part(mine, &shard, &comm);
  });
}

}  // namespace trackassoc
