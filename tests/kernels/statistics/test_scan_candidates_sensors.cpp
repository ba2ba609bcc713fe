// The per-scan candidate index over many sensors at once (kernels/statistics/scan_candidates.hpp,
// scan_candidate_pairs over a span of sensors): each sensor pair's slot holds exactly the pairs of
// the naive O(n_a·n_b·K) scan, whether the sensors' coverages overlap, touch or lie far apart, with
// asynchronous spans, gaps of validity and one wide covariance among small ones.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/statistics/scan_candidates.hpp"

namespace trackassoc {
namespace {

// n tracks of one sensor around (cx, cy) (±half on each axis), each over a random span of the K
// common times, valid at ~80 % of them, moving 30 m per step; position variance 1e4..5e4 m² (one
// track `wide_var`, when > 0).
AlignedTracks make_sensor(int32_t sensor, double cx, double cy, double half, int32_t n, int32_t K,
                          uint64_t seed, double wide_var = 0.0) {
  AlignedTracks x;
  x.sensor = sensor;
  x.dim = 4;
  x.n_times = K;
  CounterRng rng(seed, 0, 0);
  std::vector<int32_t> begin, length;
  for (int32_t i = 0; i < n; ++i) {
    x.track.push_back(i);
    x.truth.push_back(i);
    const auto b = static_cast<int32_t>(rng.uniform(0.0, K - 1.0));
    begin.push_back(b);
    length.push_back(1 + static_cast<int32_t>(rng.uniform(0.0, K - b - 1.0)));
  }
  x.allocate(begin, length);
  for (int32_t i = 0; i < n; ++i) {
    const double px = cx + rng.uniform(-half, half), py = cy + rng.uniform(-half, half);
    const double var = i == 3 && wide_var > 0.0 ? wide_var : rng.uniform(1e4, 5e4);
    for (int32_t k = x.span(i).begin; k < x.span(i).end; ++k) {
      const int64_t c = x.cell(i, k);
      x.valid[c] = rng.uniform(0.0, 1.0) < 0.8;
      const double s[4] = {px + 30.0 * k, py, 30.0, 0.0};
      const double p[10] = {var, 0.0, 0.0, 0.0, var, 0.0, 0.0, 1.0, 0.0, 1.0};
      std::copy_n(s, 4, x.state_at(c));
      std::copy_n(p, 10, x.cov_at(c));
    }
  }
  return x;
}

TEST(ScanCandidatesSensors, EverySensorPairEqualsTheNaiveScan) {
  const int32_t K = 40;
  // 0 and 1 overlap, 2 overlaps 1 by 500 m only, 3 is 10⁴ km away, 4 overlaps 0 with one
  // track of variance 10¹³ m², whose bound √((10¹³ + σ²)·c) reaches sensor 3 at c = 18.47
  // (1.36·10⁷ m) but not at c = 1 (3.2·10⁶ m).
  const std::vector<AlignedTracks> x{
      make_sensor(0, 0.0, 0.0, 3000.0, 150, K, 1), make_sensor(1, 4000.0, 0.0, 3000.0, 150, K, 2),
      make_sensor(2, 9500.0, 0.0, 3000.0, 120, K, 3), make_sensor(3, 1e7, 0.0, 3000.0, 100, K, 4),
      make_sensor(4, 0.0, 2000.0, 3000.0, 80, K, 5, 1e13)};
  std::vector<const AlignedTracks*> ptr;
  for (const auto& s : x) ptr.push_back(&s);
  for (const double cap : {1.0, 18.47}) {
    const std::vector<CandidatePairs> all = scan_candidate_pairs(ptr, cap);
    ASSERT_EQ(all.size(), 25u);
    std::size_t total = 0;
    for (int32_t s = 0; s < 5; ++s)
      for (int32_t t = 0; t < 5; ++t) {
        const CandidatePairs& got = all[s * 5 + t];
        if (t <= s) {
          EXPECT_EQ(got.size(), 0u);
          continue;
        }
        SCOPED_TRACE(std::to_string(s) + "-" + std::to_string(t) + " cap " + std::to_string(cap));
        const CandidatePairs naive = scan_candidate_pairs_all_pairs(x[s], x[t], cap);
        EXPECT_EQ(got.n_a, x[s].n_tracks());
        EXPECT_EQ(got.n_b, x[t].n_tracks());
        EXPECT_EQ(got.a, naive.a);  // sorted by (a, b), as the naive scan's
        EXPECT_EQ(got.b, naive.b);
        const CandidatePairs two = scan_candidate_pairs(x[s], x[t], cap);
        EXPECT_EQ(two.a, naive.a);
        EXPECT_EQ(two.b, naive.b);
        total += got.size();
      }
    // Far apart: nothing, except through the wide track of sensor 4.
    EXPECT_EQ(all[0 * 5 + 3].size(), 0u);
    EXPECT_EQ(all[3 * 5 + 4].size() > 0, cap > 10.0);
    EXPECT_EQ(all[1 * 5 + 3].size(), 0u);
    EXPECT_EQ(all[0 * 5 + 2].size(), 0u);  // 3.5 km between the boxes, bounds ≤ 1.4 km
    EXPECT_GT(all[0 * 5 + 1].size(), 10u);
    EXPECT_GT(all[1 * 5 + 2].size(), cap > 10.0 ? 5u : 0u);  // the boxes overlap by 500 m
    EXPECT_GT(total, 100u);
  }
}

}  // namespace
}  // namespace trackassoc
