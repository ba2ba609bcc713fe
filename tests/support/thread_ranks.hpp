// N fake ranks in one process, for tests of the sharding layer (engine/distributed/) without MPI:
// each rank is a thread, scatter and gather go through shared slots between two barriers, as
// MPI_Scatterv / MPI_Gatherv do between processes. Rank 0 runs in the calling thread.
#pragma once

#include <barrier>
#include <exception>
#include <stdexcept>
#include <thread>
#include <vector>

#include "engine/distributed/communicator.hpp"
#include "engine/distributed/shard_items.hpp"

namespace trackassoc::testing {

class ThreadRank final : public distributed::Communicator {
 public:
  struct Shared {
    explicit Shared(int n) : slots(n), sync(n) {}
    std::vector<distributed::Bytes> slots;
    std::barrier<> sync;
  };
  ThreadRank(int r, int n, Shared* shared) : r_(r), n_(n), shared_(shared) {}
  int rank() const override { return r_; }
  int size() const override { return n_; }
  distributed::Bytes scatter(const std::vector<distributed::Bytes>& parts) override {
    if (r_ == 0) {
      if (static_cast<int>(parts.size()) != n_) throw std::logic_error("scatter: one part per rank");
      shared_->slots = parts;
    }
    shared_->sync.arrive_and_wait();
    distributed::Bytes mine = shared_->slots[r_];
    stats_.bytes_received += mine.size();
    shared_->sync.arrive_and_wait();
    if (r_ == 0)
      for (const auto& p : parts) stats_.bytes_sent += p.size();
    return mine;
  }
  std::vector<distributed::Bytes> gather(const distributed::Bytes& mine) override {
    shared_->slots[r_] = mine;
    stats_.bytes_sent += mine.size();
    shared_->sync.arrive_and_wait();
    std::vector<distributed::Bytes> all;
    if (r_ == 0) {
      all = shared_->slots;
      for (const auto& b : all) stats_.bytes_received += b.size();
    }
    shared_->sync.arrive_and_wait();
    return all;
  }
  [[noreturn]] void abort(int) override { throw std::logic_error("abort"); }

 private:
  int r_, n_;
  Shared* shared_;
};

// Runs f(comm) on n ranks at once: rank 0 in this thread (its answer returned, its exception
// rethrown), ranks 1..n-1 in threads; `failures[r]` receives rank r's exception (null: none).
template <class F>
auto over_thread_ranks(int n, F f, std::vector<std::exception_ptr>* failures = nullptr) {
  ThreadRank::Shared shared(n);
  std::vector<std::exception_ptr> errors(n);
  std::vector<std::thread> threads;
  for (int r = 1; r < n; ++r)
    threads.emplace_back([&, r] {
      ThreadRank comm(r, n, &shared);
      try {
        f(comm);
      } catch (...) {
        errors[r] = std::current_exception();
      }
    });
  struct Join {
    std::vector<std::thread>& t;
    ~Join() {
      for (auto& x : t) x.join();
    }
  } join{threads};
  ThreadRank root(0, n, &shared);
  try {
    auto answer = f(root);
    distributed::end_items(root);  // as `associate` does: the serving ranks' loop returns
    for (auto& x : threads) x.join();
    threads.clear();
    if (failures) *failures = errors;
    return answer;
  } catch (...) {
    distributed::release_waiting_ranks(root, std::current_exception());  // as main.cpp does
    for (auto& x : threads) x.join();
    threads.clear();
    if (failures) *failures = errors;
    throw;
  }
}

}  // namespace trackassoc::testing
