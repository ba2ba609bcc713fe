// The candidate search tells its buffers to an AllocationGauge before allocating them
// (kernels/core/allocation_gauge.hpp, kernels/statistics/scan_candidates.hpp), so that the engine
// can refuse a search whose hits would exceed the memory budget before they are allocated (issues
// 30 and 31). Checked on a crowd whose hits are known by hand: the count is never below what the
// search holds, what it holds on return is exactly its output, and a limit is refused at the
// buffer that would cross it, with nothing held past the limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/statistics/gate_candidates.hpp"

namespace trackassoc {
namespace {

// n tracks of one sensor at the same point at every one of K common times, valid throughout,
// position variance 10⁴ m²: every pair of two such sensors is within its bound at every scan.
AlignedTracks crowd(int32_t sensor, int32_t n, int32_t K) {
  AlignedTracks x;
  x.sensor = sensor;
  x.dim = 4;
  x.n_times = K;
  for (int32_t i = 0; i < n; ++i) {
    x.track.push_back(i);
    x.truth.push_back(i);
  }
  x.allocate(std::vector<int32_t>(n, 0), std::vector<int32_t>(n, K));
  for (int32_t i = 0; i < n; ++i)
    for (int32_t k = 0; k < K; ++k) {
      const int64_t c = x.cell(i, k);
      x.valid[c] = 1;
      double* st = x.state_at(c);
      st[0] = 1000.0;
      st[1] = 2000.0;
      st[2] = st[3] = 0.0;
      double* p = x.cov_at(c);
      for (int r = 0; r < 4; ++r) p[packed_index(4, r, r)] = r < 2 ? 1e4 : 1.0;
    }
  return x;
}

struct Refused : std::runtime_error {
  Refused() : std::runtime_error("over the limit") {}
};

// By hand, n = 300, K = 16 (two blocks of 8 scans): each scan finds all n² = 90 000 pairs, so each
// block's buffer holds at least its 90 000 distinct hits of 12 bytes until the merge, which reserves
// the 2 × 90 000 of both blocks while they are still held: at least 4.32 MB at once (more with the
// buffers' growth and the duplicates a block holds between its compactions). The output: 90 000
// pairs, 8 bytes each (720 000 bytes).
constexpr int32_t kN = 300, kK = 16;
constexpr double kPairs = double{kN} * kN;
constexpr double kHeldAtTheMerge = 2.0 * kPairs * 12.0 + 2.0 * kPairs * 12.0;

TEST(ScanCandidatesGauge, CountsNoLessThanTheSearchHoldsAndEndsAtItsOutput) {
  const AlignedTracks a = crowd(0, kN, kK), b = crowd(1, kN, kK);
  const AlignedTracks* both[2] = {&a, &b};
  double most = 0.0;
  AllocationGauge gauge([&](double held, double request, bool) {
    EXPECT_LE(request, held);
    most = std::max(most, held);
  });
  const std::vector<CandidatePairs> out = scan_candidate_pairs(both, 18.0, 1.0, &gauge);
  ASSERT_EQ(out[1].size(), static_cast<std::size_t>(kPairs));
  EXPECT_GE(most, kHeldAtTheMerge);
  EXPECT_EQ(gauge.held(), 8.0 * kPairs);
  // The prune keeps every pair (they coincide): a byte of flags each, then the 8 bytes of each kept
  // pair beside the input; on return the flags are released and the kept pairs added.
  const CandidatePairs kept = prune_by_position_bound(a, b, out[1], StatisticOptions{}, &gauge);
  EXPECT_EQ(kept.size(), out[1].size());
  EXPECT_EQ(gauge.held(), 16.0 * kPairs);
  // Without a gauge, the same pairs.
  const std::vector<CandidatePairs> plain = scan_candidate_pairs(both, 18.0, 1.0);
  EXPECT_EQ(plain[1].a, out[1].a);
  EXPECT_EQ(plain[1].b, out[1].b);
}

TEST(ScanCandidatesGauge, ALimitIsRefusedBeforeTheBufferThatWouldCrossIt) {
  const AlignedTracks a = crowd(0, kN, kK), b = crowd(1, kN, kK);
  const AlignedTracks* both[2] = {&a, &b};
  const double limit = 2e6;  // below the 4.32 MB the search holds at its merge
  double most_accepted = 0.0;
  int refusals = 0;
  AllocationGauge gauge([&](double held, double, bool) {
    if (held > limit) {
      ++refusals;
      throw Refused();
    }
    most_accepted = std::max(most_accepted, held);
  });
  EXPECT_THROW(scan_candidate_pairs(both, 18.0, 1.0, &gauge), Refused);
  EXPECT_GE(refusals, 1);
  EXPECT_LE(most_accepted, limit);
  EXPECT_GT(most_accepted, 0.0);  // the index and the first buffers were within it
  // A refused buffer is not counted: what the gauge holds is what was accepted.
  EXPECT_LE(gauge.held(), limit);
}

}  // namespace
}  // namespace trackassoc
