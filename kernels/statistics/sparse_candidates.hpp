// Sparse gated candidates for large recorded track sets (docs/design.md §4.3, "Sparse form").
//
// The dense path computes the sequential statistic λ (seed 000 Eq. 1–2) for all n_a·n_b pairs of
// two sensors. At n = 10⁴ tracks per sensor that is 10⁸ pairs per sensor pair. Here a uniform grid
// over the tracks' time-averaged positions returns only the pairs that can pass the chi-square
// gate, and λ is computed for those pairs alone.
//
// Why no gated-in pair is lost (the bound). Let a pair be valid at the same K' common times (the
// usual case: both tracks exist over the whole common interval), d_k = x̂_a(k) − x̂_b(k),
// C_k = P_a(k) + P_b(k), p = the position components, T = χ²_p(D·K') the gate. Then
//   1. d_{k,p}ᵀ C_{k,pp}⁻¹ d_{k,p} ≤ d_kᵀ C_k⁻¹ d_k     (a marginal Mahalanobis distance is at most the
//                                                      full one: it minimises over the other components)
//   2. |d_{k,p}|² ≤ μ_max(C_{k,pp}) · d_{k,p}ᵀ C_{k,pp}⁻¹ d_{k,p},  μ_max(C_pp) ≤ σ²_a + σ²_b, where σ²_x
//      is the largest eigenvalue of track x's position covariance over its valid times;
//   3. |m̄_a − m̄_b|² = |mean_k d_{k,p}|² ≤ mean_k |d_{k,p}|²      (Jensen), m̄ = time-averaged position.
// Together: λ ≤ T  ⇒  |m̄_a − m̄_b|² ≤ (σ²_a + σ²_b) · T / K' = (σ²_a + σ²_b) · ρ(K').  T/K' is about D (1 +
// z·√(2/(D K'))), so the search radius is about √D standard deviations instead of the √T of a single-time
// gate. Tracks valid at only some common times (births, deaths, asynchronous coverage): a pair's common valid
// set V (K' = |V| ≥ 1 for any gated-in pair) may differ from each track's own valid set, whose mean the index
// holds. The mean over V is a convex combination of the track's valid positions, so it lies within the
// track's trajectory radius r_x = max_k |x_p(k) − m̄_x| of m̄_x; and ρ(K') ≤ ρ(1). So for any pair that is not
// "full" (both valid at all K times) the index uses the conservative
//   |m̄_a − m̄_b| ≤ √((σ²_a + σ²_b)·ρ(1)) + r_a + r_b,
// which no gated-in pair can violate either. The bound is therefore lossless for every validity
// pattern; the price is a larger radius, and more candidates, for the partial tracks only.
// `radius_scale` (≥ 1) multiplies both radii, as a margin for numerical round-off.
//
// Index: uniform grids (one cell size for full × full pairs, one for pairs with a partial track),
// points of sensor b sorted by cell; each track of sensor a looks at the 3^m neighbouring cells
// (m = 1, 2 or 3) by binary search.
// Complexity: O((n_a + n_b) log n_b + 3^m n_a log n_b + candidates) time, O(n + candidates) memory.
// λ for the candidates reuses the dense kernel (kernels/statistics/association_statistic.hpp) on per-row
// sub-problems, so the statistic is computed by one piece of code.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

// The uniform grid of both candidate indexes (this one and kernels/statistics/scan_candidates.hpp): the cell
// of a point p (m ≤ 3 coordinates) for cell size h, clamped so a far point cannot overflow.
using GridCell = std::array<int64_t, 3>;
inline GridCell grid_cell_of(const double* p, int m, double h) {
  GridCell c{0, 0, 0};
  constexpr double kLimit = 4.0e18;
  for (int d = 0; d < m; ++d) c[d] = static_cast<int64_t>(std::clamp(std::floor(p[d] / h), -kLimit, kLimit));
  return c;
}

// What the index needs of each aligned track.
struct TrackIndexKeys {
  int32_t spatial_dim = 2;                    // m
  std::vector<double> mean_position;          // [track·m + c], averaged over the track's valid times
  std::vector<double> max_position_variance;  // σ²: largest eigenvalue of the position covariance
  std::vector<int32_t> valid_times;           // number of common times where the track is valid
  std::vector<double> trajectory_radius;      // r: largest distance of a valid position from the mean
};

// O(Σ spans·m³). Tracks never valid get valid_times = 0 and are never candidates.
TrackIndexKeys track_index_keys(const AlignedTracks& tracks);

struct CandidateOptions {
  double gate_probability = 0.99;  // the chi-square gate of StatisticOptions; must be < 1
  double radius_scale = 1.0;       // ≥ 1: widens the bound radius (asynchronous valid sets)
  void validate() const;
};

// Pairs (a[q], b[q]) sorted by a then b.
struct CandidatePairs {
  int32_t n_a = 0, n_b = 0;
  std::vector<int32_t> a, b;
  std::size_t size() const { return a.size(); }
};

// The pairs that satisfy the bound above, found through the grid. Parallel over rows of `a`
// (TBB), deterministic order.
CandidatePairs gated_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b,
                                     const CandidateOptions& options);

// The same pairs by the O(n_a·n_b) scan (the naive peer for tests and benchmarks).
CandidatePairs gated_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b,
                                               const CandidateOptions& options);

// λ on a list of pairs: the sparse counterpart of PairStatistic, in the pair order given.
struct SparsePairStatistic {
  int32_t n_a = 0, n_b = 0;
  std::vector<int32_t> a, b;
  std::vector<double> lambda;
  std::vector<int32_t> dof;
  std::vector<uint8_t> in_gate;
  std::size_t size() const { return a.size(); }
  // Index q of pair (ia, ib), or -1. Requires pairs sorted by (a, b). O(log size).
  int64_t find(int32_t ia, int32_t ib) const;
  std::size_t bytes() const { return size() * (2 * sizeof(int32_t) + sizeof(double) + sizeof(int32_t) + 1); }
};

// The aligned rows `rows` of `x` copied into `out` (same times and dim; track and truth of each),
// each over its span: the sub-problems below, and the tracks a sensor pair's statistic needs when
// it is solved on another MPI rank (engine/pipeline/pair_statistics_sharded.hpp).
void copy_rows(const AlignedTracks& x, std::span<const int32_t> rows, AlignedTracks& out);

// seed 000 Eq. 1–2 for the listed pairs, through independent_sequential_statistic on per-row
// sub-problems; the gate is χ²_p(D·times) as in the dense kernel. O(pairs · K · D³), TBB over rows.
SparsePairStatistic sparse_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                                const CandidatePairs& pairs, const StatisticOptions& options);

// Keeps the pairs inside the gate.
SparsePairStatistic keep_in_gate(const SparsePairStatistic& s);

}  // namespace trackassoc
