// What a kernel holds while it runs, told to its caller BEFORE each large allocation, so that a
// stage whose memory grows with what it finds (the candidate pairs, whose number is known only once
// found) can be refused before it allocates, not after (issues 30 and 31: no stage may allocate
// past --memory-budget). The kernels know nothing of the budget (engine -> io -> kernels): the
// caller's `check` receives the bytes the kernel will hold once the allocation is made (all its
// live buffers and the new one), the allocation's own bytes and whether other threads may be
// allocating at the same time (`concurrent`), and throws to refuse (the engine:
// io/memory_budget.hpp, which also reads the resident set, where freed buffers the allocator
// keeps still count). Thread-safe: buffers of several threads are counted together, each
// allocation is added before it is made and released after it is freed, so the count is never
// below what the kernel holds (capacities, not sizes).
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

namespace trackassoc {

class AllocationGauge {
 public:
  using Check = std::function<void(double held_bytes, double request_bytes, bool concurrent)>;
  explicit AllocationGauge(Check check) : check_(std::move(check)) {}

  // Counts `bytes` about to be allocated, then checks the total; a refusal (check throws) leaves
  // the count as it was and propagates.
  void add(double bytes, bool concurrent = false) {
    if (!(bytes > 0.0)) return;
    const double now = held_.fetch_add(bytes) + bytes;
    try {
      check_(now, bytes, concurrent);
    } catch (...) {
      held_.fetch_sub(bytes);
      throw;
    }
  }
  void release(double bytes) {
    if (bytes > 0.0) held_.fetch_sub(bytes);
  }
  double held() const { return held_.load(); }

 private:
  Check check_;
  std::atomic<double> held_{0.0};
};

// gauge->add(bytes, concurrent) when there is a gauge.
inline void gauge_add(AllocationGauge* gauge, double bytes, bool concurrent = false) {
  if (gauge) gauge->add(bytes, concurrent);
}
inline void gauge_release(AllocationGauge* gauge, double bytes) {
  if (gauge) gauge->release(bytes);
}

// v.push_back(x), doubling the capacity as std::vector does, with the new buffer counted on the
// gauge before it is allocated and the old one released once moved (both are held meanwhile);
// called from parallel loops (concurrent).
template <class T>
void gauged_push_back(std::vector<T>& v, const T& x, AllocationGauge* gauge) {
  if (gauge && v.size() == v.capacity()) {
    const std::size_t old_cap = v.capacity(), new_cap = old_cap < 512 ? 1024 : 2 * old_cap;
    gauge->add(static_cast<double>(new_cap * sizeof(T)), true);
    v.reserve(new_cap);
    gauge->release(static_cast<double>(old_cap * sizeof(T)));
  }
  v.push_back(x);
}

// v.reserve(n), its growth counted first (as a concurrent request) and the old buffer released.
template <class T>
void gauged_reserve(std::vector<T>& v, std::size_t n, AllocationGauge* gauge) {
  if (n <= v.capacity()) return;
  const std::size_t old_cap = v.capacity();
  if (gauge) gauge->add(static_cast<double>(n * sizeof(T)), true);
  v.reserve(n);
  if (gauge) gauge->release(static_cast<double>(old_cap * sizeof(T)));
}

}  // namespace trackassoc
