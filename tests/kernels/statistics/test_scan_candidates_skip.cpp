// The count filter's interior skipping (kernels/statistics/scan_candidates.hpp): at odd scans only the
// pairs with a track near its span's ends (or with gaps) are searched, and a pair short of the least
// at the scans searched is tested at the others. Checked against brute force: the margin against
// every window of scans, the filter's output against each pair's count over every common scan, and
// a pair within its bound at exactly the least scans, as many of them as can be on skipped ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "kernels/statistics/chi_square.hpp"
#include "kernels/statistics/gate_candidates.hpp"
#include "kernels/statistics/scan_bound.hpp"
#include "kernels/statistics/scan_candidates.hpp"
#include "tests/support/candidate_pairs.hpp"
#include "tests/support/crossing_tracks.hpp"

namespace trackassoc {
namespace {

using testing_support::crossing_sensor;
using testing_support::pairs_of;

// Every pair of gap-free spans on K common times, its odd scans inside both tracks' margins (those the
// index may leave unsearched) counted one by one: fewer than the least for its common scans.
TEST(ScanCandidatesSkip, TheMarginsLeaveEveryPairOfSpansFewerSkippedScansThanTheLeast) {
  for (const int D : {4, 6})
    for (const double p : {0.99, 0.999})
      for (const int32_t K : {16, 40}) {
        SCOPED_TRACE("D " + std::to_string(D) + ", p " + std::to_string(p) + ", K " + std::to_string(K));
        StatisticOptions statistic;
        statistic.gate_probability = p;
        const std::vector<int32_t> least = least_scans_within_bound(D, statistic, K);
        const InteriorMargins by = interior_skip_margins(least, K);
        int64_t failures = 0, skippable = 0;
        for (int32_t b1 = 0; b1 < K; ++b1)
          for (int32_t e1 = b1 + 1; e1 <= K; ++e1)
            for (int32_t b2 = 0; b2 < K; ++b2)
              for (int32_t e2 = b2 + 1; e2 <= K; ++e2) {
                const int32_t B = std::max(b1, b2), E = std::min(e1, e2);
                if (B >= E) continue;
                const int32_t m1 = by.of({b1, e1}, K), m2 = by.of({b2, e2}, K);
                int32_t skipped = 0;
                for (int32_t k = B; k < E; ++k)
                  skipped +=
                      k % 2 == 1 && k - b1 >= m1 && e1 - 1 - k >= m1 && k - b2 >= m2 && e2 - 1 - k >= m2;
                failures += skipped >= least[E - B];
                skippable += skipped;
              }
        EXPECT_EQ(failures, 0);
        EXPECT_GT(skippable, 0);
      }
  // By hand: D = 6, p = 0.999 (the scale study's tracks), K = 16. least[6] = 1: all 6 scans of a
  // 6-scan overlap must be searched, R(6) = 6 − 2 + 2 = 6, so a track of 6 scans or more takes margin 3;
  // two whole tracks share all 16 scans, least[16] = 7, R(16) = 16 − 14 + 2 = 4: margin 2, and the odd
  // scans 3, 5, …, 13 (6 of 16) go unsearched, the pigeonhole's most (16 − 7 + 1 = 10 searched).
  StatisticOptions statistic;
  statistic.gate_probability = 0.999;
  const std::vector<int32_t> least = least_scans_within_bound(6, statistic, 16);
  ASSERT_EQ(least[6], 1);
  ASSERT_EQ(least[16], 7);
  const InteriorMargins by = interior_skip_margins(least, 16);
  EXPECT_EQ(by.by_length[5], 3);  // R(5) = 5 − 2 + 2 = 5
  EXPECT_EQ(by.by_length[16], 3);
  EXPECT_EQ(by.whole, 2);
  // A table of ones (a pair within once is kept) leaves no track an interior.
  const InteriorMargins ones = interior_skip_margins(std::vector<int32_t>(13, 1), 12);
  for (int32_t l = 1; l <= 12; ++l) EXPECT_GE(2 * ones.by_length[l], l) << l;
  EXPECT_GE(2 * ones.whole, 12);
}

int32_t gaps_of(const AlignedTracks& x, int32_t i) {
  int32_t g = 0;
  for (int32_t k = x.span(i).begin; k < x.span(i).end; ++k) g += !x.valid[x.cell(i, k)];
  return g;
}

// The count filter by brute force: every pair's scans within its bound counted over every common
// scan, kept when it has at least one and the least for its lower bound of common valid scans.
std::vector<std::pair<int32_t, int32_t>> naive_filter(const AlignedTracks& a, const AlignedTracks& b,
                                                      double c, const std::vector<int32_t>& least,
                                                      std::size_t& within_somewhere) {
  std::vector<std::pair<int32_t, int32_t>> kept;
  for (int32_t i = 0; i < a.n_tracks(); ++i)
    for (int32_t j = 0; j < b.n_tracks(); ++j) {
      int32_t count = 0;
      for (int32_t k = 0; k < a.n_times; ++k) {
        const int64_t ca = a.cell(i, k), cb = b.cell(j, k);
        count += ca >= 0 && cb >= 0 && a.valid[ca] && b.valid[cb] && within_scan_bound(a, ca, b, cb, 2, c);
      }
      if (count == 0) continue;
      ++within_somewhere;
      const int64_t n =
          static_cast<int64_t>(common_span(a.span(i), b.span(j)).size()) - gaps_of(a, i) - gaps_of(b, j);
      const auto at = static_cast<std::size_t>(std::clamp<int64_t>(n, 0, std::ssize(least) - 1));
      if (count >= least[at]) kept.emplace_back(i, j);
    }
  return kept;
}

TEST(ScanCandidatesSkip, TheFilteredPairsAreThoseOfTheNaiveCount) {
  const int32_t K = 40;
  const StatisticOptions statistic;
  const double c = chi_square_quantile(statistic.cap_probability, 4);
  const std::vector<AlignedTracks> x{crossing_sensor(0, 240, K, 31, true),
                                     crossing_sensor(1, 240, K, 32, true),
                                     crossing_sensor(2, 180, K, 33, true)};
  const std::vector<const AlignedTracks*> ptr{&x[0], &x[1], &x[2]};
  const std::vector<int32_t> least = least_scans_within_bound(4, statistic, K);
  std::vector<std::size_t> found;
  const std::vector<CandidatePairs> got = scan_candidate_pairs(ptr, c, 1.0, nullptr, least, &found);
  std::size_t kept = 0, found_all = 0, within_all = 0;
  for (const auto& [s, t] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
    SCOPED_TRACE(std::to_string(s) + "-" + std::to_string(t));
    std::size_t within = 0;
    const auto want = naive_filter(x[s], x[t], c, least, within);
    EXPECT_EQ(pairs_of(got[s * 3 + t]), want);
    EXPECT_LE(found[s * 3 + t], within);  // found at the scans searched
    kept += want.size();
    found_all += found[s * 3 + t];
    within_all += within;
  }
  EXPECT_GT(kept, 100u);
  EXPECT_LT(kept, within_all / 2);   // the filter drops most pairs of crossing tracks
  EXPECT_LT(found_all, within_all);  // and some pairs are within only at scans left out
}

// For every length n of a common span and both parities of its first scan, and for two tracks over
// every common time, a pair of tracks over that span, track i of sensor 1 on track i of sensor 0 at
// the scans of W and 10 km off at the others (σ = 100 m: far outside the bound; the pairs 100 km
// apart). W holds least[n] scans: the odd ones inside the tracks' margin (those the index may skip;
// never all of W, if the margins keep their promise), then others; a second pair of each has one
// scan fewer. The filter keeps exactly the first ones, as the count says, though most of their
// scans within are skipped.
TEST(ScanCandidatesSkip, PairsWithinAtTheLeastScansMostlySkippedAreKept) {
  const int32_t K = 40;
  const StatisticOptions statistic;
  const double c = chi_square_quantile(statistic.cap_probability, 4);
  const std::vector<int32_t> least = least_scans_within_bound(4, statistic, K);
  const InteriorMargins by = interior_skip_margins(least, K);
  std::vector<int32_t> begin, length;
  std::vector<std::vector<int32_t>> within;
  std::vector<std::pair<int32_t, int32_t>> spans{{0, K}};
  for (int32_t n = 1; n + 2 <= K; ++n) spans.emplace_back(1, n), spans.emplace_back(2, n);
  for (const auto& [b, n] : spans)
    for (const int32_t fewer : {0, 1}) {
      const int32_t h = least[n] - fewer, L = by.of({b, b + n}, K);
      if (h < 1) continue;
      std::vector<int32_t> W;
      for (int32_t k = b + L; k < b + n - L && std::ssize(W) < h; ++k)
        if (k % 2 == 1) W.push_back(k);
      for (int32_t k = b; std::ssize(W) < h; ++k)
        if (std::find(W.begin(), W.end(), k) == W.end()) W.push_back(k);
      begin.push_back(b);
      length.push_back(n);
      within.push_back(W);
    }
  const auto N = static_cast<int32_t>(begin.size());
  std::vector<AlignedTracks> x(2);
  for (int32_t s = 0; s < 2; ++s) {
    AlignedTracks& t = x[s];
    t.sensor = s;
    t.dim = 4;
    t.n_times = K;
    for (int32_t i = 0; i < N; ++i) t.track.push_back(i), t.truth.push_back(i);
    t.allocate(begin, length);
    for (int32_t i = 0; i < N; ++i)
      for (int32_t k = begin[i]; k < begin[i] + length[i]; ++k) {
        const int64_t cell = t.cell(i, k);
        t.valid[cell] = 1;
        const bool on = std::find(within[i].begin(), within[i].end(), k) != within[i].end();
        double* st = t.state_at(cell);
        st[0] = 150.0 * k + (s == 1 && !on ? 10e3 : 0.0);
        st[1] = 100e3 * i;
        st[2] = 150.0;
        double* p = t.cov_at(cell);
        for (int r = 0; r < 4; ++r) p[packed_index(4, r, r)] = r < 2 ? 1e4 : 100.0;
      }
  }
  const std::vector<const AlignedTracks*> ptr{&x[0], &x[1]};
  const std::vector<CandidatePairs> got = scan_candidate_pairs(ptr, c, 1.0, nullptr, least);
  std::size_t somewhere = 0;
  const auto want = naive_filter(x[0], x[1], c, least, somewhere);
  EXPECT_EQ(pairs_of(got[1]), want);
  std::vector<std::pair<int32_t, int32_t>> full;  // the pairs with least[n] scans within
  for (int32_t i = 0; i < N; ++i)
    if (std::ssize(within[i]) == least[length[i]]) full.emplace_back(i, i);
  EXPECT_EQ(want, full);
  EXPECT_GT(full.size(), 70u);
}

}  // namespace
}  // namespace trackassoc
