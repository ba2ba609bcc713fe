// The per-scan candidate index over many sensors at once (kernels/statistics/scan_candidates.hpp,
// scan_candidate_pairs over a span of sensors): each sensor pair's slot holds exactly the pairs of
// the naive O(n_a·n_b·K) scan, whether the sensors' coverages overlap, touch or lie far apart, with
// asynchronous spans, gaps of validity and one wide covariance among small ones.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/statistics/chi_square.hpp"
#include "kernels/statistics/gate_candidates.hpp"
#include "tests/support/candidate_pairs.hpp"
#include "tests/support/crossing_tracks.hpp"

namespace trackassoc {
namespace {

using testing_support::crossing_sensor;
using testing_support::pairs_of;

// n tracks of one sensor around (cx, cy) (±half on each axis; the third axis, m = 3, in ±half
// too), each over a random span of the K common times, valid at ~80 % of them, moving 30 m per step
// along the first axis; position variance 1e4..5e4 m² (one track `wide_var`, when > 0, and with
// `spread`, variances spread over 10²..10⁶ m², so that queries cover a few to many cells). D = 2m.
AlignedTracks make_sensor(int32_t sensor, double cx, double cy, double half, int32_t n, int32_t K,
                          uint64_t seed, double wide_var = 0.0, int D = 4, bool spread = false) {
  AlignedTracks x;
  x.sensor = sensor;
  x.dim = D;
  x.n_times = K;
  const int m = D / 2;
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
    const double p0[3] = {cx + rng.uniform(-half, half), cy + rng.uniform(-half, half),
                          rng.uniform(-half, half)};
    const double var = i == 3 && wide_var > 0.0 ? wide_var
                       : spread                 ? std::pow(10.0, rng.uniform(2.0, 6.0))
                                                : rng.uniform(1e4, 5e4);
    for (int32_t k = x.span(i).begin; k < x.span(i).end; ++k) {
      const int64_t c = x.cell(i, k);
      x.valid[c] = rng.uniform(0.0, 1.0) < 0.8;
      double* st = x.state_at(c);
      for (int d = 0; d < m; ++d) st[d] = p0[d] + (d == 0 ? 30.0 * k : 0.0);
      st[m] = 30.0;
      double* p = x.cov_at(c);
      for (int r = 0; r < D; ++r) p[packed_index(D, r, r)] = r < m ? var : 1.0;
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

// 2 100 tracks a sensor (track indices of 12 bits: each scan's hits sorted by their 25-bit radix key
// in three passes, an odd number, so the sorted hits end in the merge buffer's storage), packed so
// that each scan holds far more hits than the radix sort's least count: the naive scan's pairs. A
// sort that loses or corrupts hits shows here; a wrong order alone would cost memory, not pairs
// (each block's merge keeps every hit and the final sort orders them), and is
// tests/kernels/core/test_radix_sort.cpp's.
TEST(ScanCandidatesSensors, ThreeRadixPassesGiveTheNaiveScansPairs) {
  const int32_t K = 6;
  const std::vector<AlignedTracks> x{make_sensor(0, 0.0, 0.0, 3000.0, 2100, K, 21),
                                     make_sensor(1, 500.0, 0.0, 3000.0, 2100, K, 22)};
  const std::vector<const AlignedTracks*> ptr{&x[0], &x[1]};
  const CandidatePairs got = scan_candidate_pairs(ptr, 18.47)[1];
  const CandidatePairs naive = scan_candidate_pairs_all_pairs(x[0], x[1], 18.47);
  EXPECT_GT(naive.size(), std::size_t{20000});  // ≥ 512 hits at some scan: the radix path taken
  EXPECT_EQ(got.a, naive.a);
  EXPECT_EQ(got.b, naive.b);
}

// m = 1 and m = 3, with variances over four decades: the rows of cells read along the last axis
// and the switch to reading every point give the naive scan's pairs.
TEST(ScanCandidatesSensors, OneAndThreeAxesWithSpreadRadiiEqualTheNaiveScan) {
  for (const int D : {2, 6}) {
    const int32_t K = 12;
    const std::vector<AlignedTracks> x{make_sensor(0, 0.0, 0.0, 4000.0, 300, K, 11, 0.0, D, true),
                                       make_sensor(1, 1000.0, 0.0, 4000.0, 300, K, 12, 0.0, D, true),
                                       make_sensor(2, 9000.0, 0.0, 4000.0, 200, K, 13, 0.0, D, true)};
    const std::vector<const AlignedTracks*> ptr{&x[0], &x[1], &x[2]};
    const std::vector<CandidatePairs> all = scan_candidate_pairs(ptr, 18.47);
    std::size_t total = 0;
    for (const auto& [s, t] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
      SCOPED_TRACE("D " + std::to_string(D) + " sensors " + std::to_string(s) + "-" + std::to_string(t));
      const CandidatePairs naive = scan_candidate_pairs_all_pairs(x[s], x[t], 18.47);
      EXPECT_EQ(all[s * 3 + t].a, naive.a);
      EXPECT_EQ(all[s * 3 + t].b, naive.b);
      total += naive.size();
    }
    EXPECT_GT(total, 500u) << D;
  }
}

// Sparse tracks (1 500 over 80 km, in 3-D over 40 km, bounds of ~1 km: the grid's cells widened, in 3-D to
// twice the median radius) and tracks clustered in a wide box (280 within 1 km, 20 over 80 km: widened; in
// 2-D the table form, back to the median radius, the cluster's cells being full; in 3-D the sorted form,
// kept widened), in 2-D and 3-D: the naive scan's pairs.
TEST(ScanCandidatesSensors, SparseAndClusteredTracksEqualTheNaiveScan) {
  for (const int D : {4, 6})
    for (const bool clustered : {false, true}) {
      const int32_t K = 10;
      const double half = clustered ? 500.0 : D == 4 ? 40000.0 : 20000.0;
      const int32_t n = clustered ? 300 : 1500;
      std::vector<AlignedTracks> x{make_sensor(0, 0.0, 0.0, half, n, K, 31, 0.0, D),
                                   make_sensor(1, 300.0, 0.0, half, n, K, 32, 0.0, D)};
      if (clustered)  // the last 20 tracks of each spread over ±40 km
        for (AlignedTracks& t : x)
          for (int32_t i = 280; i < 300; ++i)
            for (int32_t k = t.span(i).begin; k < t.span(i).end; ++k)
              for (int d = 0; d < D / 2; ++d) t.state_at(t.cell(i, k))[d] += 4000.0 * (i - 290) * (d + 1);
      const std::vector<const AlignedTracks*> ptr{&x[0], &x[1]};
      SCOPED_TRACE("D " + std::to_string(D) + (clustered ? " clustered" : " sparse"));
      const CandidatePairs got = scan_candidate_pairs(ptr, 18.47)[1];
      const CandidatePairs naive = scan_candidate_pairs_all_pairs(x[0], x[1], 18.47);
      EXPECT_GT(naive.size(), clustered ? 5000u : 20u);
      EXPECT_EQ(got.a, naive.a);
      EXPECT_EQ(got.b, naive.b);
    }
}

// The count filter of the calibrated gate: its table is the smallest h with (n − h)·c ≤ G(n)
// found by counting h up (G(n) = f·χ²_p(n·D/f), f ≤ n), it drops most pairs of crossing tracks, and the
// position-bound prune keeps exactly the same pairs from what it leaves as from every pair found.
TEST(ScanCandidatesSensors, TheCountFilterDropsOnlyPairsThePruneDrops) {
  const StatisticOptions statistic;  // the default calibrated gate
  const int D = 4;
  const double c = chi_square_quantile(statistic.cap_probability, D), f = statistic.scans_per_independent;
  const std::vector<int32_t> least = least_scans_within_bound(D, statistic, 60);
  ASSERT_EQ(least.size(), 61u);
  for (int32_t n = 1; n <= 60; ++n) {
    auto gate = [&](int32_t scans) {  // f ≤ n: n scans are at most n independent ones
      const double fn = std::min(f, static_cast<double>(scans));
      return fn * chi_square_quantile(statistic.gate_probability, scans * D / fn);
    };
    const double G = gate(n);
    int32_t h = 1;
    while ((n - h) * c > G) ++h;
    int32_t smallest = h;  // over n' ≥ n, as the table holds a lower bound's least
    for (int32_t m = n + 1; m <= 60; ++m) {
      const double Gm = gate(m);
      int32_t hm = 1;
      while ((m - hm) * c > Gm) ++hm;
      smallest = std::min(smallest, hm);
    }
    EXPECT_EQ(least[n], smallest) << n;
  }
  EXPECT_GT(least[60], 10);  // over 60 scans a pair must be within its bound at many of them

  const int32_t K = 50;
  const std::vector<AlignedTracks> x{crossing_sensor(0, 200, K, 21), crossing_sensor(1, 200, K, 22),
                                     crossing_sensor(2, 150, K, 23)};
  const std::vector<const AlignedTracks*> ptr{&x[0], &x[1], &x[2]};
  std::vector<std::size_t> found;
  const std::vector<CandidatePairs> filtered = candidate_pairs_for_gate(ptr, statistic, 1.0, nullptr, &found);
  const std::vector<CandidatePairs> every = scan_candidate_pairs(ptr, c);
  std::size_t dropped = 0, total = 0;
  for (const auto& [s, t] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
    SCOPED_TRACE(std::to_string(s) + "-" + std::to_string(t));
    const CandidatePairs& all = every[s * 3 + t];
    EXPECT_EQ(found[s * 3 + t], all.size());  // found counts the pairs before the filter
    const auto kept = pairs_of(filtered[s * 3 + t]), everything = pairs_of(all);
    EXPECT_TRUE(std::includes(everything.begin(), everything.end(), kept.begin(), kept.end()));
    const auto pruned_kept = pairs_of(prune_by_position_bound(x[s], x[t], filtered[s * 3 + t], statistic));
    const auto pruned_all = pairs_of(prune_by_position_bound(x[s], x[t], all, statistic));
    EXPECT_EQ(pruned_kept, pruned_all);
    EXPECT_GT(pruned_all.size(), 20u);
    dropped += everything.size() - kept.size();
    total += everything.size();
  }
  EXPECT_GT(dropped, total / 5);  // the filter does work here (28 % of 12 912 pairs)
}

// The per-scan bound is the position ellipse d_pᵀ C_pp⁻¹ d_p ≤ c inside the circle of the traces:
// with covariances long on the first axis (σ² 10⁶ m²) and short on the second (10² m²), a track
// 200 m off along the long axis is within (term 200²/(2·10⁶) = 0.02 ≤ c), one 200 m off along the
// short axis is not (200²/(2·10²) = 200 > c = 18.5), though both lie inside the circle
// (|d|² = 4·10⁴ ≤ 2·(10⁶ + 10²)·c): the circle alone found both.
TEST(ScanCandidatesSensors, TheBoundIsThePositionEllipse) {
  const int32_t K = 5;
  auto sensor = [&](int32_t id, std::vector<std::array<double, 2>> at) {
    AlignedTracks x;
    x.sensor = id;
    x.dim = 4;
    x.n_times = K;
    const auto n = static_cast<int32_t>(at.size());
    for (int32_t i = 0; i < n; ++i) x.track.push_back(i), x.truth.push_back(i);
    x.allocate(std::vector<int32_t>(at.size(), 0), std::vector<int32_t>(at.size(), K));
    for (int32_t i = 0; i < n; ++i)
      for (int32_t k = 0; k < K; ++k) {
        const int64_t c = x.cell(i, k);
        x.valid[c] = 1;
        double* st = x.state_at(c);
        st[0] = at[i][0], st[1] = at[i][1], st[2] = st[3] = 0.0;
        double* p = x.cov_at(c);
        const double var[4] = {1e6, 1e2, 1.0, 1.0};
        for (int r = 0; r < 4; ++r) p[packed_index(4, r, r)] = var[r];
      }
    return x;
  };
  const AlignedTracks a = sensor(0, {{0.0, 0.0}, {0.0, 50000.0}});
  const AlignedTracks b = sensor(1, {{200.0, 0.0}, {0.0, 50200.0}});
  const double c = chi_square_quantile(StatisticOptions{}.cap_probability, 4);
  ASSERT_LT(c, 200.0);
  ASSERT_LE(200.0 * 200.0, 2.0 * (1e6 + 1e2) * c);  // both pairs inside the circle
  const std::vector<std::pair<int32_t, int32_t>> along_the_long_axis{{0, 0}};
  EXPECT_EQ(pairs_of(scan_candidate_pairs(a, b, c)), along_the_long_axis);
  EXPECT_EQ(pairs_of(scan_candidate_pairs_all_pairs(a, b, c)), along_the_long_axis);
}

}  // namespace
}  // namespace trackassoc
