// Thin oneTBB wrappers (docs/design.md §2, Threads), after oneTBB's `seismic` example: every parallel
// kernel is written as a serial function over an index range [begin, end), and these wrappers
// split the range across the task arena. The thread count is set once by the caller through
// tbb::global_control (the CLI's --threads).
#pragma once

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include <cstddef>

namespace trackassoc {

// Calls kernel(begin, end) on disjoint sub-ranges covering [0, n). `grain` is the smallest
// sub-range worth a task. The static partitioner makes the split independent of timing, which
// matters only for kernels that are themselves deterministic per element (all of ours are).
template <class RangeKernel>
void parallel_for_range(std::size_t n, std::size_t grain, RangeKernel&& kernel) {
  if (n == 0) return;
  if (grain == 0) grain = 1;
  if (n <= grain) {
    kernel(std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) { kernel(r.begin(), r.end()); },
      tbb::static_partitioner());
}

}  // namespace trackassoc
