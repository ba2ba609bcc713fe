// The search geometry of the per-scan candidate index (kernels/statistics/scan_candidates.hpp):
// the bound on each position block's largest eigenvalue that sets a track's ball, the cells a
// ball reads in the table of cells, and the one-pass form for tracks of even spreads. Every pair
// inside its position ellipse at a scan must be found, and the ellipse is worked out here by Eigen
// or by the naive O(n_a·n_b·K) scan.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/statistics/scan_candidates.hpp"
#include "kernels/statistics/scan_search.hpp"
#include "tests/support/candidate_pairs.hpp"

namespace trackassoc {
namespace {

using testing_support::pairs_of;

// One scan of n tracks with position blocks `blocks` (m × m each) at `at`; velocity variances 1.
AlignedTracks one_scan_sensor(int32_t id, int m, const std::vector<Eigen::VectorXd>& at,
                              const std::vector<Eigen::MatrixXd>& blocks) {
  AlignedTracks x;
  x.sensor = id;
  x.dim = 2 * m;
  x.n_times = 1;
  const auto n = static_cast<int32_t>(at.size());
  for (int32_t i = 0; i < n; ++i) x.track.push_back(i), x.truth.push_back(i);
  x.allocate(std::vector<int32_t>(n, 0), std::vector<int32_t>(n, 1));
  const int D = 2 * m;
  for (int32_t i = 0; i < n; ++i) {
    const int64_t cell = x.cell(i, 0);
    x.valid[cell] = 1;
    for (int d = 0; d < m; ++d) x.state_at(cell)[d] = at[i](d);
    double* p = x.cov_at(cell);
    for (int r = 0; r < D; ++r)
      for (int col = r; col < D; ++col)
        p[packed_index(D, r, col)] = r < m && col < m ? blocks[i](r, col) : (r == col ? 1.0 : 0.0);
  }
  return x;
}

// The search ball and the bound on the largest eigenvalue of each position block
// (kernels/statistics/scan_bound.hpp, position_spread), against the ellipse worked out here by Eigen: every
// pair whose d_pᵀ(P_a + P_b)⁻¹d_p ≤ c at its one scan is found and no other, in 2-D and 3-D, for isotropic
// covariances equal on both sides (the trace is m times the largest eigenvalue, and the query's ball is the
// ellipse), the same σ on every track (one pass) or σ² over three decades (two passes), and rotated ones with
// axes 10:1, on a dense box (the table of cells) and a sparse one (the sorted cells). Half of b's tracks sit
// just inside a's ellipse (1 − 10⁻⁶ of the boundary along a random direction, or along an axis) and half just
// outside (1 + 10⁻⁶). It fails with the spread 0.5 % short, or the table's ball 3 % short (checked by hand).
TEST(ScanCandidatesBall, EveryPairInsideTheEllipseIsFoundAtItsBoundary) {
  const double c = 16.27;  // χ²₃(0.999)
  enum Kind { kEven, kSpread, kRotated };
  for (const int m : {2, 3})
    for (const Kind kind : {kEven, kSpread, kRotated})
      for (const double half : {3000.0, 300000.0}) {
        const bool isotropic = kind != kRotated;
        SCOPED_TRACE("m " + std::to_string(m) +
                     (kind == kEven     ? " even"
                      : kind == kSpread ? " spread"
                                        : " rotated") +
                     " box " + std::to_string(half));
        const int32_t n = 300;  // one scan: a pair missed there is missed
        CounterRng rng(static_cast<uint64_t>(m * 10 + kind), half > 1e4, 7);
        auto random_block = [&]() {  // even: σ² 5·10³ on every track; spread: 10²..10⁵
          Eigen::MatrixXd block =
              Eigen::MatrixXd::Identity(m, m) * (kind == kEven ? 5e3 : std::pow(10.0, rng.uniform(2.0, 5.0)));
          if (isotropic) return block;
          Eigen::MatrixXd g(m, m);
          for (int r = 0; r < m; ++r)
            for (int col = 0; col < m; ++col) g(r, col) = rng.normal();
          const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(g).householderQ();
          Eigen::VectorXd axes = Eigen::VectorXd::Constant(m, 1e3);
          axes(0) = 1e4;
          return Eigen::MatrixXd(q * axes.asDiagonal() * q.transpose());
        };
        std::vector<Eigen::MatrixXd> block_a(n), block_b(n);
        std::vector<Eigen::VectorXd> at_a(n, Eigen::VectorXd(m)), at_b(n);
        for (int32_t i = 0; i < n; ++i) {
          block_a[i] = random_block();
          block_b[i] = isotropic ? block_a[i] : random_block();  // (equal: the ball is tight)
          for (int d = 0; d < m; ++d) at_a[i](d) = rng.uniform(-half, half);
          // A random direction for half the tracks, an axis for the rest (the chord of the ball
          // along a row, or the gap to a row), b's track on the boundary along it.
          Eigen::VectorXd u = Eigen::VectorXd::Zero(m);
          if (i % 4 < 2)
            for (int d = 0; d < m; ++d) u(d) = rng.normal();
          else
            u(std::min(m - 1, static_cast<int>(rng.uniform(0.0, m)))) =
                rng.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
          const Eigen::MatrixXd sum = block_a[i] + block_b[i];
          const double boundary = std::sqrt(c / u.dot(sum.llt().solve(u)));
          at_b[i] = at_a[i] + u * boundary * (i % 2 == 0 ? 1.0 - 1e-6 : 1.0 + 1e-6);
        }
        const AlignedTracks a = one_scan_sensor(0, m, at_a, block_a),
                            b = one_scan_sensor(1, m, at_b, block_b);
        std::vector<std::pair<int32_t, int32_t>> expected;  // the ellipse alone, every pair
        for (int32_t i = 0; i < n; ++i)
          for (int32_t j = 0; j < n; ++j) {
            const Eigen::VectorXd dp = at_a[i] - at_b[j];
            if (dp.dot((block_a[i] + block_b[j]).llt().solve(dp)) <= c) expected.emplace_back(i, j);
          }
        std::size_t inside = 0;
        for (const auto& [i, j] : expected) inside += i == j && i % 2 == 0;
        EXPECT_EQ(inside, static_cast<std::size_t>(n / 2));  // every pair placed inside is within
        EXPECT_EQ(pairs_of(scan_candidate_pairs(a, b, c)), expected);
      }
}

// Points on the faces of the grid's cells and pairs on their boundary: a's tracks at integer
// multiples of the cell size h = √(2·s·c) (the median radius, for tracks of one spread s) far from
// the origin (up to 10⁸ h, where u = x/h rounds), b's at exactly the boundary distance
// √((s_a + s_b)·c) and 10⁻¹², 10⁻¹⁵ and 4·10⁻¹⁰ either side of it, along axes, diagonals and
// random directions; m = 1, 2, 3; spreads even (one pass; b's 1.5 times a's, so the pass runs from
// b), uneven (two passes) and over decades. The index's pairs equal the naive scan's. (A fresh-eyed
// review's stress check: it fails with the ball's 10⁻⁹ and 10⁻⁶ widening removed, or the ball
// 10⁻⁴ short.)
TEST(ScanCandidatesBall, PairsOnCellFacesAndOnTheirBoundaryEqualTheNaiveScan) {
  const double cap = 16.27;
  const double offsets[] = {0.0, -37.0, 1e3, -1e5, 1e6, 1e7, 1e8};
  std::size_t pairs = 0;
  for (int m = 1; m <= 3; ++m)
    for (const double offset : offsets)
      for (int trial = 0; trial < 24; ++trial) {
        SCOPED_TRACE("m " + std::to_string(m) + " offset " + std::to_string(offset) + " trial " +
                     std::to_string(trial));
        CounterRng rng(99, static_cast<uint64_t>(m),
                       static_cast<uint64_t>(offset < 0 ? 100 - offset : offset),
                       static_cast<uint64_t>(trial));
        const int n = 200;
        const double s = trial % 2 == 1 ? 5e3 : std::pow(10.0, rng.uniform(1.0, 4.0));
        const double h = std::sqrt(2.0 * s * (1.0 + 1e-8) * cap);  // (position_spread widens s)
        std::vector<Eigen::VectorXd> pa(n, Eigen::VectorXd(m)), pb(n, Eigen::VectorXd(m));
        std::vector<Eigen::MatrixXd> va(n), vb(n);
        for (int i = 0; i < n; ++i) {
          double sa = s, sb = s;
          if (trial % 4 == 2) sb = 1.5 * s;                                      // even, the pass from b
          if (trial % 4 == 3) sb = rng.uniform(0.0, 1.0) < 0.5 ? s : 100.0 * s;  // two passes
          if (trial % 8 >= 6)
            sa = s * std::pow(10.0, std::floor(rng.uniform(0.0, 4.0))),
            sb = s * std::pow(10.0, std::floor(rng.uniform(0.0, 4.0)));
          va[i] = Eigen::MatrixXd::Identity(m, m) * sa;
          vb[i] = Eigen::MatrixXd::Identity(m, m) * sb;
          for (int d = 0; d < m; ++d)
            pa[i](d) = offset * h + (rng.uniform(0.0, 1.0) < 0.7 ? std::floor(rng.uniform(-8.0, 8.0))
                                                                 : rng.uniform(-8.0, 8.0)) *
                                        h;
          const double factors[] = {1.0, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 4e-10, 1.0 - 1e-15};
          const double distance =
              std::sqrt((sa + sb) * cap) * factors[static_cast<int>(rng.uniform(0.0, 5.0))];
          Eigen::VectorXd dir = Eigen::VectorXd::Zero(m);
          const int kind = m == 1 ? 0 : static_cast<int>(rng.uniform(0.0, 3.0));
          if (kind == 0)
            dir(std::min(m - 1, static_cast<int>(rng.uniform(0.0, m)))) =
                rng.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
          for (int d = 0; d < m && kind > 0; ++d)
            dir(d) = kind == 1 ? (rng.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0) : rng.normal();
          pb[i] = pa[i] + dir.normalized() * distance;
        }
        const AlignedTracks a = one_scan_sensor(0, m, pa, va), b = one_scan_sensor(1, m, pb, vb);
        const auto naive = pairs_of(scan_candidate_pairs_all_pairs(a, b, cap));
        EXPECT_EQ(pairs_of(scan_candidate_pairs(a, b, cap)), naive);
        pairs += naive.size();
      }
  EXPECT_GT(pairs, 3u * 7u * 24u * 50u);  // the pairs placed on their boundary are mostly within
}

// A position block that is not positive semi-definite beside a larger one whose sum is positive
// definite: P_a = diag(1, −0.9)·10⁴, P_b = diag(0.5, 1)·10⁴, C = diag(1.5, 0.1)·10⁴. P_a's trace
// (10³) is no bound on its largest eigenvalue (10⁴), so the index takes its Gershgorin row sum; a
// pair at d'C⁻¹d = 0.81·c along the first axis (|d|² = 1.215·10⁴·c) is found. With the trace the
// circle held (0.1 + 1)·10⁴·c and lost it.
TEST(ScanCandidatesBall, ABlockThatIsNotSemiDefiniteBesideALargerOneKeepsItsPairs) {
  const double cap = 16.27;
  Eigen::MatrixXd block_a(2, 2), block_b(2, 2);
  block_a << 1e4, 0.0, 0.0, -0.9e4;
  block_b << 0.5e4, 0.0, 0.0, 1e4;
  Eigen::VectorXd xa(2), xb(2);
  xa << 0.0, 0.0;
  xb << 0.9 * std::sqrt(1.5e4 * cap), 0.0;  // d'C⁻¹d = 0.81·c
  const AlignedTracks a = one_scan_sensor(0, 2, {xa}, {block_a}), b = one_scan_sensor(1, 2, {xb}, {block_b});
  const std::vector<std::pair<int32_t, int32_t>> found{{0, 0}};
  EXPECT_EQ(pairs_of(scan_candidate_pairs(a, b, cap)), found);
}

// Two passes (spreads over four decades on both sides) with a block of negative variances on b
// (spread < 0, its ball's radius NaN) beside a wider one on a: the pair is within (|d| = 0, C
// positive definite) and found from a's side only, so each pair is one hit of the scan (the count
// filter sums a block's hits into numbers of scans; with the side rule r_a ≥ r_b for b's pass the
// NaN radius passed both and the pair was counted twice).
TEST(ScanCandidatesBall, APairIsOneHitOfAScanWhenABallIsNaN) {
  const double cap = 16.27;
  std::vector<Eigen::VectorXd> at_a, at_b;
  std::vector<Eigen::MatrixXd> blocks_a, blocks_b;
  CounterRng rng(7, 0, 0);
  for (int32_t i = 0; i < 40; ++i) {
    Eigen::VectorXd x(2);
    x << rng.uniform(0.0, 2000.0), rng.uniform(0.0, 2000.0);
    at_a.push_back(x);
    at_b.push_back(x + Eigen::Vector2d(rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0)));
    blocks_a.push_back(Eigen::Matrix2d::Identity() * std::pow(10.0, 2.0 + 4.0 * i / 39.0));
    blocks_b.push_back(Eigen::Matrix2d::Identity() * std::pow(10.0, 6.0 - 4.0 * i / 39.0));
  }
  blocks_b[39] = Eigen::Matrix2d::Identity() * -4e5;  // beside a's track 39 (10⁶ m²), same place
  at_b[39] = at_a[39];
  const AlignedTracks a = one_scan_sensor(0, 2, at_a, blocks_a), b = one_scan_sensor(1, 2, at_b, blocks_b);
  const AlignedTracks* both[2] = {&a, &b};
  const std::vector<ValidByTime> valid{valid_by_time(a), valid_by_time(b)};
  ScanSearch search;
  std::vector<ScanHit> hits;
  search.scan(both, valid, 0, cap, hits, nullptr);
  std::multiset<std::pair<int32_t, int32_t>> found;
  for (const ScanHit& h : hits) found.emplace(h.a, h.b);
  EXPECT_EQ(found.count({39, 39}), 1u);
  const std::set<std::pair<int32_t, int32_t>> distinct(found.begin(), found.end());
  EXPECT_EQ(distinct.size(), found.size());
  EXPECT_GT(found.size(), 20u);  // (the pairs of one target, and some neighbours)
}

}  // namespace
}  // namespace trackassoc
