// Sharding and failure agreement over ranks (engine/distributed/sharding.hpp).
#include "engine/distributed/sharding.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <stdexcept>

#include "engine/distributed/shard_items.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc::distributed {
namespace {

enum class Status : uint8_t { kOk = 0, kInputError = 1, kInternalError = 2 };

int exit_code(Status s) { return s == Status::kInputError ? 2 : 1; }

// The status and message of a thrown exception.
std::pair<Status, std::string> status_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const SilentExit& x) {
    return {x.code() == 2 ? Status::kInputError : Status::kInternalError, ""};
  } catch (const InputError& x) {
    return {Status::kInputError, x.what()};
  } catch (const std::exception& x) {
    return {Status::kInternalError, x.what()};
  } catch (...) {
    return {Status::kInternalError, "unknown exception"};
  }
}

Bytes failure_message(Status s, const std::string& message) {
  ByteWriter w;
  w.put<uint8_t>(static_cast<uint8_t>(s));
  w.put(message);
  return w.take();
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

ShardTimes& shard_times() {
  static ShardTimes times;
  return times;
}

}  // namespace

const ShardTimes& last_shard_times() { return shard_times(); }

int owner_of_item(int64_t item, int ranks) { return static_cast<int>(item % ranks); }

std::vector<int32_t> balance_by_cost(const std::vector<double>& cost, int ranks) {
  std::vector<int32_t> order(cost.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return cost[a] > cost[b]; });
  std::vector<double> load(ranks, 0.0);
  std::vector<int32_t> owner(cost.size(), 0);
  for (int32_t t : order) {
    const auto r = static_cast<int32_t>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[t] = r;
    load[r] += cost[t];
  }
  return owner;
}

double makespan(const std::vector<double>& cost, const std::vector<int32_t>& assignment, int ranks) {
  std::vector<double> load(ranks, 0.0);
  for (std::size_t t = 0; t < cost.size(); ++t) load[assignment[t]] += cost[t];
  return load.empty() ? 0.0 : *std::max_element(load.begin(), load.end());
}

void inject_fault_for_tests(const Communicator& comm, const std::string& shard) {
  const char* v = std::getenv("TRACKASSOC_FAULT_RANK");
  if (v && std::atoi(v) == comm.rank())
    throw std::runtime_error("fault injected for the test (TRACKASSOC_FAULT_RANK) in " + shard);
}

std::vector<Bytes> gather_shards(Communicator& comm, const std::function<Bytes(std::string& shard)>& work) {
  comm.set_exchange_open(true);
  std::string shard = "its shard";
  Bytes mine;
  Status own = Status::kOk;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = cpu_seconds();
  try {
    Bytes payload = work(shard);
    ByteWriter head;  // status, then the work's wall and CPU seconds, then the payload
    head.put<uint8_t>(static_cast<uint8_t>(Status::kOk));
    head.put(seconds_since(wall0));
    head.put(cpu_seconds() - cpu0);
    mine = head.take();
    mine.insert(mine.end(), payload.begin(), payload.end());
  } catch (...) {
    const auto [s, message] = status_of(std::current_exception());
    own = s;
    mine = failure_message(s, shard + ": " + message);
  }
  std::vector<Bytes> all = comm.gather(mine);
  comm.set_exchange_open(false);
  if (!comm.root()) {
    if (own != Status::kOk) throw SilentExit(exit_code(own));
    return {};
  }
  for (std::size_t r = 0; r < all.size(); ++r) {
    const auto s = static_cast<Status>(all[r].at(0));
    if (s == Status::kOk) continue;
    ByteReader rd(all[r].data() + 1, all[r].size() - 1);
    const std::string what = "rank " + std::to_string(r) + ", " + rd.get_string();
    if (s == Status::kInputError) throw InputError(what);
    throw std::runtime_error(what);
  }
  ShardTimes& times = shard_times();
  times = {};
  for (auto& b : all) {
    ByteReader rd(b.data() + 1, b.size() - 1);
    times.wall_s.push_back(rd.get<double>());
    times.cpu_s.push_back(rd.get<double>());
    b.erase(b.begin(), b.begin() + 1 + 2 * sizeof(double));
  }
  return all;
}

Bytes scatter_work(Communicator& comm, const std::vector<Bytes>& parts) {
  comm.set_exchange_open(true);
  std::vector<Bytes> framed;
  if (comm.root()) {
    framed.reserve(parts.size());
    for (const auto& p : parts) {
      Bytes b;
      b.reserve(p.size() + 1);
      b.push_back(static_cast<uint8_t>(Status::kOk));
      b.insert(b.end(), p.begin(), p.end());
      framed.push_back(std::move(b));
    }
    comm.set_ranks_waiting(false);
  }
  Bytes mine = comm.scatter(framed);
  const auto s = static_cast<Status>(mine.at(0));
  if (s != Status::kOk) {
    comm.set_exchange_open(false);
    throw SilentExit(exit_code(s));
  }
  mine.erase(mine.begin());
  return mine;
}

void check_on_root(Communicator& comm, const std::function<void()>& check) {
  if (comm.size() == 1) return check();
  std::exception_ptr error;
  Bytes status{static_cast<uint8_t>(Status::kOk)};
  if (comm.root()) try {
      check();
    } catch (...) {
      error = std::current_exception();
      const auto [s, message] = status_of(error);
      status = failure_message(s, message);
    }
  comm.set_exchange_open(true);
  const Bytes mine = comm.scatter(std::vector<Bytes>(comm.root() ? comm.size() : 0, status));
  comm.set_exchange_open(false);
  if (error) std::rethrow_exception(error);
  const auto s = static_cast<Status>(mine.at(0));
  if (s != Status::kOk) throw SilentExit(exit_code(s));
}

void release_waiting_ranks(Communicator& comm, const std::exception_ptr& error) {
  if (!comm.root() || !comm.ranks_waiting()) return;
  comm.set_ranks_waiting(false);
  const auto [s, message] = status_of(error);
  comm.scatter(std::vector<Bytes>(comm.size(), failure_message(s, message)));
  comm.set_exchange_open(false);
}

std::vector<Bytes> encode_planned_parts(int ranks, const std::vector<int32_t>& rank_of,
                                        const std::function<void(ByteWriter&, uint64_t items)>& header,
                                        const std::function<void(std::size_t k, ByteWriter&)>& encode_item) {
  std::vector<ByteWriter> w(ranks);
  std::vector<uint64_t> count(ranks, 0);
  for (int32_t r : rank_of) ++count.at(r);
  for (int r = 0; r < ranks; ++r) header(w[r], count[r]);
  std::vector<Bytes> encoded(rank_of.size());
  parallel_for_range(rank_of.size(), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t k = lo; k < hi; ++k) {
      ByteWriter out;
      encode_item(k, out);
      encoded[k] = out.take();
    }
  });
  for (std::size_t k = 0; k < rank_of.size(); ++k) {
    auto& bytes = w[rank_of[k]].bytes();
    bytes.insert(bytes.end(), encoded[k].begin(), encoded[k].end());
    Bytes().swap(encoded[k]);
  }
  std::vector<Bytes> parts;
  for (auto& x : w) parts.push_back(x.take());
  return parts;
}

void solve_part_items(std::size_t n, const std::function<void(std::size_t k)>& solve,
                      const std::function<std::string(std::size_t k)>& describe, std::string* shard) {
  std::vector<std::exception_ptr> errors(n);  // rethrown as thrown: bad input stays bad input
  parallel_for_range(n, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t k = lo; k < hi; ++k) try {
        solve(k);
      } catch (...) {
        errors[k] = std::current_exception();
      }
  });
  for (std::size_t k = 0; k < n; ++k) {
    if (!errors[k]) continue;
    if (shard) *shard = describe(k);
    std::rethrow_exception(errors[k]);
  }
}

std::vector<double> cost_share_per_rank(const std::vector<double>& cost, const std::vector<int32_t>& rank_of,
                                        int ranks) {
  std::vector<double> load(ranks, 0.0);
  double total = 0.0;
  for (std::size_t k = 0; k < cost.size(); ++k) {
    load.at(rank_of[k]) += cost[k];
    total += cost[k];
  }
  for (double& l : load) l = total > 0 ? l / total : 0.0;
  return load;
}

void print_item_shard_stats(const char* what, const ItemShardStats& stats) {
  if (!std::getenv("TRACKASSOC_MPI_STATS")) return;
  const int N = stats.ranks;
  const std::vector<double> share = cost_share_per_rank(stats.cost, stats.rank_of, N);
  std::vector<int> count(N, 0);
  for (int32_t r : stats.rank_of) ++count[r];
  double total = 0.0, largest = 0.0;
  for (double c : stats.cost) total += c, largest = std::max(largest, c);
  std::string per_rank;
  for (int r = 0; r < N; ++r)
    per_rank += (r ? ", " : "") + std::to_string(count[r]) + " (" + std::to_string(share[r]) + ")";
  std::fprintf(
      stderr,
      "mpi: %d ranks, %zu %s (the largest %.3f of the estimated cost), per rank: items (share of cost): "
      "%s; scattered %llu B, gathered %llu B; plan+encode %.3f s, rank 0 solve %.3f s, solve+gather "
      "%.3f s\n",
      N, stats.cost.size(), what, total > 0 ? largest / total : 0.0, per_rank.c_str(),
      static_cast<unsigned long long>(stats.scattered), static_cast<unsigned long long>(stats.gathered),
      stats.plan_s, stats.rank0_solve_s, stats.exchange_s);
}

}  // namespace trackassoc::distributed
