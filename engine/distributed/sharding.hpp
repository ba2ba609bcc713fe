// Sharding work over the ranks of a Communicator (docs/design.md §8; issue 19), and the rules that keep a
// failure from hanging a job or leaving a partial output.
//
// What goes where:
//   * Monte Carlo runs: item i (a run of one configuration, flattened in the order one process
//     visits them) goes to rank i mod N (round robin; the runs of a study cost about the same,
//     and consecutive configurations of different cost are dealt out evenly). Each run's random
//     stream comes from (seed, run) alone (kernels/core/random.hpp), never from the rank, so the
//     rows are those of one process; rank 0 puts them back in item order (sharded_items). An
//     item may hold more than one run where the runs must stay together (seed002: a motion's
//     runs are one filter bank), or be a scene (seed003) or an instance (schedules).
//   * Connected components: balance_by_cost, longest processing time first (Graham 1969: within
//     4/3 of the best makespan), cost = an estimate of the component's solve.
//
// Failures (issue 19 item 4). Every message a rank sends starts with a status: ok, bad input or
// internal error with its message. So
//   * a rank whose shard throws still takes part in the gather; rank 0 then throws the first
//     failure, "rank R, SHARD: why" (InputError → exit 2, else exit 1), writes nothing, and the
//     failing rank ends with the same status (SilentExit);
//   * rank 0 failing before it hands out work (bad input file: exit 2, one line) scatters the
//     failure instead of the work (release_waiting_ranks), and the waiting ranks end silently.
// Test hook: TRACKASSOC_FAULT_RANK=R makes rank R's first item throw (tests/mpi/).
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "engine/distributed/byte_buffer.hpp"
#include "engine/distributed/codec.hpp"
#include "engine/distributed/communicator.hpp"

namespace trackassoc::distributed {

// The rank that runs item `item` of `items` over `ranks` ranks (round robin).
int owner_of_item(int64_t item, int ranks);

// Rank of every task, longest processing time first: tasks by cost descending (ties by index),
// each to the least loaded rank (ties: the lowest rank). Deterministic; costs must be >= 0.
std::vector<int32_t> balance_by_cost(const std::vector<double>& cost, int ranks);

// The largest load of any rank under `assignment` (for the scaling note).
double makespan(const std::vector<double>& cost, const std::vector<int32_t>& assignment, int ranks);

// Test hook: throws on the rank named by TRACKASSOC_FAULT_RANK (an internal error).
void inject_fault_for_tests(const Communicator& comm, const std::string& shard);

// Every rank runs work(shard) once; `shard` is the description the work keeps current (e.g.
// "seed000 run 7"), named in the message when it throws. Rank 0 returns every rank's payload in
// rank order, or throws the first failure; the other ranks return nothing (or SilentExit when
// their own work failed).
std::vector<Bytes> gather_shards(Communicator& comm, const std::function<Bytes(std::string& shard)>& work);

// Rank 0, after gather_shards: each rank's time in its work, wall and CPU (this process) seconds,
// for the scaling note (printed by main.cpp under TRACKASSOC_MPI_STATS). The CPU time is the
// work's cost without the other ranks' contention when ranks share cores (--oversubscribe).
struct ShardTimes {
  std::vector<double> wall_s, cpu_s;
};
const ShardTimes& last_shard_times();

// Rank 0: hands parts[r] to rank r (with an ok status) and returns its own; the others return
// theirs, or end with SilentExit when rank 0 sent a failure.
Bytes scatter_work(Communicator& comm, const std::vector<Bytes>& parts);

// Rank 0 runs `check` (e.g. the output paths, which only rank 0 writes) and every rank learns its
// outcome: rank 0 rethrows a failure, the others end with SilentExit. One rank: just check().
void check_on_root(Communicator& comm, const std::function<void()>& check);

// Rank 0, before it throws: if the other ranks wait for scatter_work, send them `error` instead.
void release_waiting_ranks(Communicator& comm, const std::exception_ptr& error);

// The parts of work planned item by item (e.g. components; rank_of[k] = the rank of item k): part
// r is header(w, items_of_r) followed by the bytes encode_item(k, w) of its items in plan order.
// The items are encoded in parallel (TBB), then appended in order.
std::vector<Bytes> encode_planned_parts(int ranks, const std::vector<int32_t>& rank_of,
                                        const std::function<void(ByteWriter&, uint64_t items)>& header,
                                        const std::function<void(std::size_t k, ByteWriter&)>& encode_item);

// Runs solve(k) for the n items of a part in parallel (TBB). When some throw, the first in part
// order is named: *shard = describe(k) (the failure protocol above), and its exception rethrown.
void solve_part_items(std::size_t n, const std::function<void(std::size_t k)>& solve,
                      const std::function<std::string(std::size_t k)>& describe, std::string* shard);

// Each rank's share of the total cost under `rank_of` (for the TRACKASSOC_MPI_STATS lines).
std::vector<double> cost_share_per_rank(const std::vector<double>& cost, const std::vector<int32_t>& rank_of,
                                        int ranks);

// The rows of items 0..items-1 computed over the ranks (owner_of_item), in item order on rank 0
// (empty elsewhere). `run(i)` gives item i's rows, `describe(i)` names it in an error; a row
// travels by its declared codec (engine/distributed/codec.hpp: wire_codec(Row), or its bytes when
// it is trivially copyable). With `parallel`, a rank runs its items at once over its TBB
// threads (solve_part_items: each item's rows kept apart, then taken in item order, the first
// failing item named), for runs that share nothing; else one after the other.
template <class Row>
std::vector<Row> sharded_items(Communicator& comm, int64_t items,
                               const std::function<std::vector<Row>(int64_t)>& run,
                               const std::function<std::string(int64_t)>& describe, bool parallel = false) {
  const int N = comm.size();
  // The rows of this rank's items, mine[k] = its k-th; `shard` names the item being run.
  auto run_mine = [&](const std::vector<int64_t>& mine, std::string& shard) {
    std::vector<std::vector<Row>> rows(mine.size());
    if (!parallel) {
      for (std::size_t k = 0; k < mine.size(); ++k) {
        shard = describe(mine[k]);
        if (N > 1) inject_fault_for_tests(comm, shard);
        rows[k] = run(mine[k]);
      }
      return rows;
    }
    solve_part_items(
        mine.size(),
        [&](std::size_t k) {
          if (N > 1 && k == 0) inject_fault_for_tests(comm, describe(mine[k]));
          rows[k] = run(mine[k]);
        },
        [&](std::size_t k) { return describe(mine[k]); }, &shard);
    return rows;
  };
  std::vector<int64_t> mine;
  for (int64_t i = comm.rank(); i < items; i += N) mine.push_back(i);
  if (N == 1) {
    std::string shard;
    std::vector<Row> rows;
    for (auto& v : run_mine(mine, shard))
      for (auto& r : v) rows.push_back(std::move(r));
    return rows;
  }
  const auto parts = gather_shards(comm, [&](std::string& shard) {
    const std::vector<std::vector<Row>> rows = run_mine(mine, shard);
    ByteWriter w;
    for (std::size_t k = 0; k < mine.size(); ++k) {
      w.put<int64_t>(mine[k]);
      w.put<uint64_t>(rows[k].size());
      for (const auto& r : rows[k]) codec_detail::put_value(w, r);
    }
    return w.take();
  });
  if (!comm.root()) return {};
  std::vector<std::vector<Row>> by_item(items);
  for (const auto& part : parts) {
    ByteReader rd(part);
    while (!rd.done()) {
      const auto i = rd.get<int64_t>();
      const auto n = rd.get<uint64_t>();
      for (uint64_t k = 0; k < n; ++k) codec_detail::get_value(rd, by_item.at(i).emplace_back());
    }
  }
  std::vector<Row> rows;
  for (auto& v : by_item)
    for (auto& r : v) rows.push_back(std::move(r));
  return rows;
}

}  // namespace trackassoc::distributed
