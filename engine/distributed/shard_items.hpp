// Work items planned by rank 0 and solved over the ranks (docs/design.md §8): the connected
// components of the default (sparse S-D) path and of --sparse, or any work that only rank 0 can
// build (it alone reads the input) but every rank can solve from what it is sent.
//
// A path declares its job once: the header every item of a part shares (the solver and its
// options), the item (a component's self-contained problem) and its result, each with a declared
// codec (engine/distributed/codec.hpp), and the solve; jobs that one serve loop answers (the
// default path's gated statistics, then its components) differ by their `kind`. Then
//   1. rank 0 plans: each item to a rank by its estimated cost, longest processing time first
//      (balance_by_cost, engine/distributed/sharding.hpp);
//   2. rank 0 builds the items (in parallel, TBB) and scatters each rank its part: the header,
//      then (position, id, item) per item;
//   3. every rank (rank 0 too) solves its part's items in parallel (TBB) and sends back
//      (position, result) per item; the other ranks do this in serve_items;
//   4. rank 0 returns the results in plan order, the order of one process.
// A solve that reads nothing rank-dependent gives the results of one process for any N.
// Failures follow engine/distributed/sharding.hpp: the part ("rank 1, 12 components (40
// tracks): ...") or the item that failed ("rank 1, component 17 (12 tracks): ...") is named.
// With TRACKASSOC_MPI_STATS set, rank 0 prints one line on stderr per sharded solve: items per
// rank and their share of the estimated cost, bytes scattered and gathered, and the times.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/distributed/codec.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/distributed/sharding.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc::distributed {

// A kind of work shared out item by item. Header, Item and Result travel by their codecs.
template <class H, class I, class R>
struct ItemJob {
  using Header = H;
  using Item = I;
  using Result = R;
  const char* noun;  // what an item is, in messages and the stats line: "component"
  const char* unit;  // what an item's size counts: "tracks"
  std::size_t (*size)(const I&);
  R (*solve)(const H&, const I&);
  uint8_t kind = 0;  // the first byte of each part: which job of serve_items' list it is
};

// What rank 0 learned about a sharded solve (the TRACKASSOC_MPI_STATS line).
struct ItemShardStats {
  int ranks = 0;
  std::vector<double> cost;
  std::vector<int32_t> rank_of;
  uint64_t scattered = 0, gathered = 0;
  double plan_s = 0, rank0_solve_s = 0, exchange_s = 0;
};
// Prints the stats line on stderr when TRACKASSOC_MPI_STATS is set (engine/distributed/sharding.cpp).
void print_item_shard_stats(const char* what, const ItemShardStats& stats);

namespace item_detail {

// A part solved: the header and items decoded, solved in parallel, (position, result) encoded.
template <class Job>
Bytes solve_part(const Job& job, const Bytes& part, std::string& shard, const Communicator& comm) {
  ByteReader rd(part);
  if (rd.get<uint8_t>() != job.kind) throw std::runtime_error("distributed work part of another job (a bug)");
  typename Job::Header header;
  codec_detail::get_value(rd, header);
  const auto n = static_cast<std::size_t>(rd.get<uint64_t>());
  std::vector<uint64_t> position(n);
  std::vector<int64_t> id(n);
  std::vector<typename Job::Item> items(n);
  std::size_t units = 0;
  for (std::size_t k = 0; k < n; ++k) {
    position[k] = rd.get<uint64_t>();
    id[k] = rd.get<int64_t>();
    codec_detail::get_value(rd, items[k]);
    units += job.size(items[k]);
  }
  if (!rd.done()) throw std::runtime_error("distributed work part longer than its items (a bug)");
  shard = std::to_string(n) + " " + job.noun + "s (" + std::to_string(units) + " " + job.unit + ")";
  if (comm.size() > 1) inject_fault_for_tests(comm, shard);
  std::vector<typename Job::Result> results(n);
  solve_part_items(
      n, [&](std::size_t k) { results[k] = job.solve(header, items[k]); },
      [&](std::size_t k) {
        return std::string(job.noun) + " " + std::to_string(id[k]) + " (" +
               std::to_string(job.size(items[k])) + " " + job.unit + ")";
      },
      &shard);
  ByteWriter w;
  for (std::size_t k = 0; k < n; ++k) {
    w.put<uint64_t>(position[k]);
    codec_detail::put_value(w, results[k]);
  }
  return w.take();
}

}  // namespace item_detail

// Rank 0: items 0..cost.size()-1, item k named by id[k] and built by make_item(k) (called in
// parallel), solved over the ranks of `comm`; returns result k at k. The other ranks run
// serve_items(comm, job) at the same time. `what` names the solve in the stats line.
template <class Job>
std::vector<typename Job::Result> shard_items(
    Communicator& comm, const Job& job, const char* what, const typename Job::Header& header,
    const std::vector<int64_t>& id, const std::vector<double>& cost,
    const std::function<typename Job::Item(std::size_t k)>& make_item) {
  if (id.size() != cost.size()) throw std::logic_error("shard_items: one id and one cost per item");
  ItemShardStats stats;
  stats.ranks = comm.size();
  stats.cost = cost;
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t sent0 = comm.stats().bytes_sent, received0 = comm.stats().bytes_received;
  stats.rank_of = balance_by_cost(cost, comm.size());
  const auto parts = encode_planned_parts(
      comm.size(), stats.rank_of,
      [&](ByteWriter& w, uint64_t items) {
        w.put<uint8_t>(job.kind);
        codec_detail::put_value(w, header);
        w.put<uint64_t>(items);
      },
      [&](std::size_t k, ByteWriter& w) {
        w.put<uint64_t>(k);
        w.put<int64_t>(id[k]);
        codec_detail::put_value(w, make_item(k));
      });
  stats.plan_s = seconds_since(t0);
  const Bytes mine = scatter_work(comm, parts);
  stats.scattered = comm.stats().bytes_sent - sent0;
  const auto t1 = std::chrono::steady_clock::now();
  std::vector<Bytes> solved;
  try {
    solved = gather_shards(comm, [&](std::string& shard) {
      shard = std::string("its ") + job.noun + "s";
      Bytes r = item_detail::solve_part(job, mine, shard, comm);
      stats.rank0_solve_s = seconds_since(t1);
      return r;
    });
  } catch (...) {
    comm.set_ranks_waiting(true);  // the others wait for the next round: release them (main.cpp)
    throw;
  }
  comm.set_ranks_waiting(true);  // until the next round's scatter or end_items
  stats.exchange_s = seconds_since(t1);
  stats.gathered = comm.stats().bytes_received - received0;
  std::vector<typename Job::Result> results(cost.size());
  std::vector<char> have(cost.size(), 0);
  for (const auto& part : solved) {
    ByteReader rd(part);
    while (!rd.done()) {
      const auto k = rd.get<uint64_t>();
      codec_detail::get_value(rd, results.at(k));
      have[k] = 1;
    }
  }
  for (std::size_t k = 0; k < cost.size(); ++k)
    if (!have[k])
      throw std::logic_error(std::string(job.noun) + " " + std::to_string(id[k]) +
                             " was solved by no rank (a bug)");
  print_item_shard_stats(what, stats);
  return results;
}

// Ranks other than 0, round after round (rank 0 may shard several solves, e.g. the registration
// stage's re-associations, and several jobs, each part's first byte naming its job's kind):
// receive a part, solve it with its job, send it back; return at the empty part of end_items.
// Rank 0's failure, or its release after a round that failed here or elsewhere
// (release_waiting_ranks), ends this rank silently (SilentExit).
template <class... Jobs>
void serve_items(Communicator& comm, const Jobs&... jobs) {
  while (true) {
    const Bytes mine = scatter_work(comm, {});
    if (mine.empty()) {
      comm.set_exchange_open(false);
      return;
    }
    try {
      gather_shards(comm, [&](std::string& shard) {
        Bytes solved;
        bool found = false;
        auto try_job = [&](const auto& job) {
          if (found || mine[0] != job.kind) return;
          found = true;
          shard = std::string("its ") + job.noun + "s";
          solved = item_detail::solve_part(job, mine, shard, comm);
        };
        (try_job(jobs), ...);
        if (!found) throw std::runtime_error("distributed work part of no job served here (a bug)");
        return solved;
      });
    } catch (const SilentExit&) {
      // This rank's part failed and rank 0 reports it: wait for its release like the others.
    }
  }
}

// Rank 0, after its last shard_items of a job: the other ranks' serve_items return. Nothing when
// no round left them waiting (one process, or no solve was sharded).
inline void end_items(Communicator& comm) {
  if (!comm.root() || comm.size() == 1 || !comm.ranks_waiting()) return;
  scatter_work(comm, std::vector<Bytes>(comm.size()));
  comm.set_exchange_open(false);
}

}  // namespace trackassoc::distributed
