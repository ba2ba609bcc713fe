// The span layout of AlignedTracks (kernels/statistics/association_statistic.hpp): each track is
// stored over its own span only, so memory is linear in the tracks' durations, and pairs whose spans
// do not meet cost nothing. The span-driven kernels are checked against the same cells laid out
// densely (every track over every common time), which is what the layout replaced.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cross_covariance.hpp"
#include "kernels/statistics/scan_candidates.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {
namespace {

// A track reporting every second over [t0, t1] of a target at (x0 + 10·t, y0) (10 m/s along x).
void add_track(TrackTable& t, int32_t sensor, int32_t track, double t0, double t1, double x0, double y0) {
  const Eigen::MatrixXd P = Eigen::Vector4d(25, 25, 1, 1).asDiagonal();
  for (double s = t0; s <= t1; s += 1.0)
    t.push_back(sensor, track, s, Eigen::Vector4d(x0 + 10.0 * s, y0, 10, 0), P, track);
}

std::vector<double> grid(int K) {
  std::vector<double> g;
  for (int k = 0; k < K; ++k) g.push_back(k);
  return g;
}

// The same tracks laid out densely: every track over all K common times (cells outside a span are
// invalid), the layout before spans.
AlignedTracks dense_copy(const AlignedTracks& x) {
  AlignedTracks d = x;
  d.allocate_full();
  for (int32_t i = 0; i < x.n_tracks(); ++i) {
    const AlignedTracks::Span sp = x.span(i);
    for (int32_t k = sp.begin; k < sp.end; ++k) {
      const int64_t from = x.cell(i, k), to = d.cell(i, k);
      d.valid[to] = x.valid[from];
      std::copy_n(x.state_at(from), x.dim, d.state_at(to));
      std::copy_n(x.cov_at(from), packed_size(x.dim), d.cov_at(to));
    }
  }
  return d;
}

// Two tracks at opposite ends of a 1000 s grid (1 s steps): reports over [10, 19] s and
// [980, 989] s. Two-sided with max_extrapolation 5 s, their spans are the times in [5, 24] and
// [975, 994]: 20 cells each, 40 in all, where the dense layout stored 2 × 1000 = 2000. Forward, a
// track exists from its first report to 5 s after its last: [10, 24] and [980, 994], 15 each.
TEST(AlignedSpans, TracksStoreOnlyTheirSpans) {
  TrackTable t(StateLayout::kXY_VXVY);
  add_track(t, 0, 1, 10.0, 19.0, 0.0, 0.0);
  add_track(t, 0, 2, 980.0, 989.0, 0.0, 0.0);
  const std::vector<double> g = grid(1000);
  AlignmentOptions o;
  o.max_extrapolation = 5.0;
  const AlignedTracks two = align_tracks(t, 0, g, o);
  ASSERT_EQ(two.n_tracks(), 2);
  EXPECT_EQ(two.span(0).begin, 5);
  EXPECT_EQ(two.span(0).end, 25);
  EXPECT_EQ(two.span(1).begin, 975);
  EXPECT_EQ(two.span(1).end, 995);
  EXPECT_EQ(two.cells(), 40);
  EXPECT_EQ(two.valid.size(), 40u);
  EXPECT_EQ(two.state.size(), 40u * 4);
  EXPECT_EQ(two.cov.size(), 40u * 10);
  EXPECT_EQ(aligned_size(t, 0, g, o).cells, 40);  // the memory check's count, before allocating
  EXPECT_EQ(aligned_size(t, 0, g, o).tracks, 2);
  EXPECT_EQ(two.cell(0, 4), -1);  // outside the span: no cell, never valid
  EXPECT_FALSE(two.valid_at(0, 4));
  EXPECT_FALSE(two.valid_at(0, 500));
  for (int k = 5; k < 25; ++k) EXPECT_TRUE(two.valid_at(0, k)) << k;  // two-sided: valid over the span
  // At 5 s the first report (10 s, x = 100) is retrodicted by 5 s: x = 50; at 994 s the last
  // (989 s, x = 9890) is predicted by 5 s: 9940.
  EXPECT_NEAR(two.state_at(two.cell(0, 5))[0], 50.0, 1e-9);
  EXPECT_NEAR(two.state_at(two.cell(1, 994))[0], 9940.0, 1e-9);

  o.method = AlignmentMethod::kForward;
  const AlignedTracks fwd = align_tracks(t, 0, g, o);
  EXPECT_EQ(fwd.span(0).begin, 10);
  EXPECT_EQ(fwd.span(0).end, 25);
  EXPECT_EQ(fwd.span(1).begin, 980);
  EXPECT_EQ(fwd.span(1).end, 995);
  EXPECT_EQ(fwd.cells(), 30);
  EXPECT_EQ(aligned_size(t, 0, g, o).cells, 30);
  // The dense layout's validity, computed by the old rule, is the same everywhere.
  for (int k = 0; k < 1000; ++k) {
    EXPECT_EQ(fwd.valid_at(0, k), k >= 10 && k <= 24) << k;
    EXPECT_EQ(fwd.valid_at(1, k), k >= 980 && k <= 994) << k;
  }
}

// A pair whose spans do not meet is never visited: its tracks' cells are made non-positive-definite,
// which any visit would report as an InputError. The statistic reports it as never coexisting
// (dof 0, outside the gate) and the candidate indexes do not return it; a pair that does meet is
// visited and fails.
TEST(AlignedSpans, PairsWhoseSpansDoNotMeetCostNoVisit) {
  TrackTable t(StateLayout::kXY_VXVY);
  add_track(t, 0, 1, 10.0, 19.0, 0.0, 0.0);
  add_track(t, 1, 5, 500.0, 509.0, 0.0, 0.0);  // same place, 480 s later
  add_track(t, 1, 6, 12.0, 30.0, 0.0, 0.0);    // overlaps track 1
  const std::vector<double> g = grid(1000);
  AlignmentOptions o;
  o.max_extrapolation = 5.0;
  AlignedTracks a = align_tracks(t, 0, g, o);
  const AlignedTracks b = align_tracks(t, 1, g, o);
  ASSERT_EQ(b.n_tracks(), 2);
  EXPECT_EQ(common_span(a.span(0), b.span(0)).size(), 0);
  EXPECT_EQ(common_span(a.span(0), b.span(1)).size(), 18);         // [7, 36) ∩ [5, 25) = [7, 25)
  for (std::size_t c = 0; c < a.cov.size(); ++c) a.cov[c] = -1e6;  // any visit throws

  AlignedTracks only_far = b;  // b's track 5 alone
  only_far.track = {5};
  only_far.truth = {5};
  const std::vector<int32_t> begin{b.span(0).begin}, length{b.span(0).size()};
  only_far.allocate(begin, length);
  std::copy_n(b.state.begin(), b.span(0).size() * 4, only_far.state.begin());
  std::copy_n(b.cov.begin(), b.span(0).size() * 10, only_far.cov.begin());
  std::copy_n(b.valid.begin(), b.span(0).size(), only_far.valid.begin());
  const PairStatistic s = independent_sequential_statistic(a, only_far, StatisticOptions{});
  EXPECT_EQ(s.dof[0], 0);
  EXPECT_EQ(s.in_gate[0], 0);
  EXPECT_EQ(s.lambda[0], 0.0);
  EXPECT_EQ(scan_candidate_pairs(a, only_far, 10.0).size(), 0u);
  EXPECT_THROW(independent_sequential_statistic(a, b, StatisticOptions{}), InputError);  // track 6 meets
}

// Random tracks with spans scattered over a 300-step grid: every span-driven kernel gives exactly
// the values of the same cells laid out densely (bit for bit: the same cells in the same order).
TEST(AlignedSpans, SpanKernelsEqualTheDenseLayout) {
  TrackTable t(StateLayout::kXY_VXVY);
  CounterRng rng(31, 2);
  for (int32_t s = 0; s < 2; ++s)
    for (int32_t i = 0; i < 40; ++i) {
      const double t0 = std::floor(rng.uniform(0.0, 260.0)), len = std::floor(rng.uniform(2.0, 60.0));
      // 20 targets 1 km apart, each in fragments (tracks i and i + 20) of both sensors.
      add_track(t, s, i, t0, std::min(t0 + len, 299.0), 1000.0 * (i % 20) + rng.uniform(-5, 5),
                rng.uniform(-5, 5));
    }
  const std::vector<double> g = grid(300);
  for (const AlignmentMethod method : {AlignmentMethod::kTwoSided, AlignmentMethod::kForward}) {
    AlignmentOptions o;
    o.method = method;
    const AlignedTracks a = align_tracks(t, 0, g, o), b = align_tracks(t, 1, g, o);
    const AlignedTracks da = dense_copy(a), db = dense_copy(b);
    EXPECT_LT(a.cells() * 3, da.cells()) << "spans cover well under a third of the grid";
    for (const double rho : {0.0, 0.3}) {
      StatisticOptions so;
      so.correlated = rho > 0.0;
      so.cross_correlation = rho;
      const PairStatistic s = independent_sequential_statistic(a, b, so),
                          d = independent_sequential_statistic(da, db, so);
      EXPECT_EQ(s.lambda, d.lambda);
      EXPECT_EQ(s.dof, d.dof);
      EXPECT_EQ(s.in_gate, d.in_gate);
      int gated = 0;
      for (uint8_t v : s.in_gate) gated += v;
      EXPECT_GT(gated, 5);
    }
    // The Bar-Shalom–Campo recursion (these constant covariances are not a filter's, so only its
    // series is compared, not a statistic that needs C to stay positive definite).
    const std::vector<double> ga = gain_complements(a, 1.0), gda = gain_complements(da, 1.0),
                              gb = gain_complements(b, 1.0), gdb = gain_complements(db, 1.0);
    for (int32_t i = 0; i < a.n_tracks(); ++i)
      for (int32_t k = a.span(i).begin; k < a.span(i).end; ++k)
        for (int e = 0; e < 16; ++e) ASSERT_EQ(ga[a.cell(i, k) * 16 + e], gda[da.cell(i, k) * 16 + e]);
    int recursions = 0;
    for (int32_t i = 0; i < a.n_tracks(); ++i)
      for (int32_t j = 0; j < b.n_tracks(); ++j) {
        if (common_span(a.span(i), b.span(j)).size() < 2) continue;
        ASSERT_EQ(cross_covariance_series(a, i, ga, b, j, gb, 1.0),
                  cross_covariance_series(da, i, gda, db, j, gdb, 1.0));
        ++recursions;
      }
    EXPECT_GT(recursions, 50);
    auto same = [](const CandidatePairs& x, const CandidatePairs& y) { return x.a == y.a && x.b == y.b; };
    EXPECT_TRUE(same(scan_candidate_pairs(a, b, 18.47), scan_candidate_pairs(da, db, 18.47)));
    EXPECT_TRUE(same(scan_candidate_pairs(a, b, 18.47), scan_candidate_pairs_all_pairs(a, b, 18.47)));
    const CandidatePairs gated = gated_candidate_pairs(a, b, CandidateOptions{0.99, 1.0});
    EXPECT_TRUE(same(gated, gated_candidate_pairs(da, db, CandidateOptions{0.99, 1.0})));
    const SparsePairStatistic sp = sparse_sequential_statistic(a, b, gated, StatisticOptions{}),
                              sd = sparse_sequential_statistic(da, db, gated, StatisticOptions{});
    EXPECT_EQ(sp.lambda, sd.lambda);
    EXPECT_EQ(sp.dof, sd.dof);
  }
}

}  // namespace
}  // namespace trackassoc
