// Candidate pairs for the calibrated gate, from a spatial index per common time (docs/design.md §4.3,
// "Sparse form"; kernels/statistics/association_statistic.hpp, GateMethod::kCalibrated). Three
// files: this driver (blocks of scans, each pair's scans within its bound counted, the count
// filter), one scan's search (kernels/statistics/scan_search.hpp) and the bound it tests
// (kernels/statistics/scan_bound.hpp).
//
// The calibrated gate accepts a pair only if at least one common scan k has a term
// dᵀC⁻¹d ≤ c (the per-scan cap). That gives a lossless spatial bound per scan:
//   dᵀC⁻¹d ≥ d_pᵀ C_pp⁻¹ d_p ≥ |d_p|² / μ_max(C_pp),   μ_max(C_pp) ≤ s_a + s_b,
// (a marginal Mahalanobis distance is at most the full one; the largest eigenvalue of a sum is at
// most the sum of the largest eigenvalues), s a bound on the largest eigenvalue of a position
// block: the smaller of its trace and its largest Gershgorin row sum P_ii + Σ_{j≠i}|P_ij|, by a
// relative 10⁻⁸ more (the trace alone is m times too large for an isotropic covariance, so in 3-D
// the search ball was √3 too wide). A pair with |d_p(k)|² > (s_a(k) + s_b(k))·c at every common scan
// cannot pass the gate. The bound is per scan, so it holds for any pattern of validity
// (late starts, early ends, asynchronous coverage), unlike a bound on time-averaged positions.
// A pair inside that ball is within its bound at k when also d_pᵀ C_pp⁻¹ d_p ≤ c (the ellipse
// inside it; the position term the position-bound prune of gate_candidates.hpp sums): radar
// covariances are long across the line of sight, and the circle around the long axis holds
// several times the ellipse's pairs (recorded_10k: 983 k pairs within the circle at some scan,
// 386 k within the ellipse, 31 539 gated either way; the count filter and the prune keep the same
// pairs, so the association is unchanged).
//
// Index: for each common time k, each sensor's valid tracks are gathered once (position, spread s),
// with their bounding box; a pair of sensors whose boxes, widened by the largest bound
// √((max s_a + max s_b)·c), do not meet is skipped at k (radars far apart), and otherwise only the
// tracks inside the other's widened box are searched: a uniform grid of cell size the median radius
// √(2·s·c) over one side's tracks, or up to twice that for sparse tracks so that a cell holds ~0.3
// of them (BM_CandidatesByDensity: 13.4 → 12.0 ms; at a tenth of the density 54 → 8.6 ms); a table
// of the cells of their box when it has at most 32 cells a track, each row of cells one range, and
// sorted by cell otherwise, a row found by binary search;
// each track of the other side looking at the cells its own radius covers (with the table, only the
// cells its ball meets: the rows within reach, each row's chord of the ball), the ellipse tested by
// its adjugate (a superset of the prune's Cholesky test by a relative 10⁻⁹). Each pair is searched
// from the side with the larger radius (two passes, one over each side's grid), or, when one side's
// spreads are even (its largest at most twice the other side's mean: tracks of one accuracy), in
// one pass over that side's grid with the ball √((s_q + max s_g)·c), which holds every pair's
// bound (of two such sides, the grid is the one whose largest spread times its mean is smaller).
// Hits are collected per block of consecutive scans (parallel over blocks, TBB; up to 65 536 of a
// block's scans at a time radix-sorted by pair, summed and merged into the block's set), then the
// blocks' sets merged, so the output does not depend on the thread count.
// Each scan indexes only the tracks valid there, listed from their spans (O(Σ spans + K)).
// Complexity: O(Σ_k Σ_s n_s(k) + Σ_k Σ_{s<t meeting at k} (n'_s + n'_t)·log n'_t + hits) time, n_s(k) the
// tracks of sensor s valid at scan k, n' those in the other's widened box; O(Σ spans + hits) memory.
// (The previous form ran every pair of sensors separately over every scan, reading each track's
// cells once per partner sensor: widearea's candidates stage took 38 s, now 2.7 s at 2 threads
// (3.9 s at 1) with the same 402 276 pairs within the circle, 256 574 within the ellipse since; at
// 2 threads 1.2 s with either; widearea_small 3.0 s, now 0.07-0.25 s;
// tests/kernels/statistics/test_scan_candidates_sensors.cpp checks every slot against the naive scan.)
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// `cap`: the per-scan cap c of the gate (SequentialGate::cap()); radius_scale ≥ 1 widens the bound.
CandidatePairs scan_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                    double radius_scale = 1.0);

// The same for every pair s < t of `sensors` at once (slot s·S + t; the other slots empty, and
// slot s·S + t equal to scan_candidate_pairs(*sensors[s], *sensors[t], ...)). Each sensor's tracks
// valid at a common time are gathered once for all its pairs, and a pair of sensors is searched at
// that time only where its bounding boxes, widened by the largest bound, meet: sensors whose
// coverages do not overlap cost one box test per scan.
// O(Σ_k Σ_s n_s(k) + Σ_k Σ_{s<t meeting at k} (search of the tracks in the overlap) + hits).
// `gauge` (optional) is told each large buffer before it is allocated (the index by time, each
// track's gaps and margin, each thread's scratch of one scan, each block's hits as they grow, their
// merge, the filter's flags, the output) and throws to refuse; on return it holds the output's
// bytes (8 a pair), the rest released.
//
// The count filter (least_hits, optional): each pair's scans within its bound are counted, and a
// pair whose lower bound n of common valid scans (|span_a ∩ span_b| less the invalid cells inside
// either span) has fewer than least_hits[min(n, size − 1)] is dropped (least_scans_within_bound
// in kernels/statistics/gate_candidates.hpp:
// lossless for the calibrated gate). With the filter, not every scan is searched for every pair
// (interior skipping, by pigeonhole): at odd common times only the pairs with a track at its edge
// there (within its margin of its span's first or last scan, or with invalid cells inside its
// span) are searched. A pair of tracks without gaps has common span [B, E) of n scans, and its
// scans within the margin m_B of B or m_E of E are at the edge of the track that starts at B or
// ends at E, so at most ⌈(n − m_B − m_E)/2⌉ of its scans go unsearched; the margins
// (interior_skip_margins: by a track's length, smaller for a track over every common time) make
// that fewer than least[n], so a pair that passes the filter is found at some scan searched. A pair
// found short of the least is then tested at its unsearched scans, one by one until it reaches the
// least or cannot (its count is the full search's, and the filter's output the same). The scans
// searched are about half of a long track's (the least is 5 of 10 common scans and 70 of 100 at
// D = 4): the scale study's defaults' candidates 22.3 → 16.1–16.4 ms (10 of 16 scans),
// docs/performance.md "Session 34". `found` (optional) gets, per slot, every pair within its bound
// at some scan searched, before the filter.
// Hits are 12 bytes (slot and count in 16 bits: S ≤ 256).
std::vector<CandidatePairs> scan_candidate_pairs(std::span<const AlignedTracks* const> sensors, double cap,
                                                 double radius_scale = 1.0, AllocationGauge* gauge = nullptr,
                                                 std::span<const int32_t> least_hits = {},
                                                 std::vector<std::size_t>* found = nullptr);

// The interior skipping's margins for the count filter's table `least_hits` on a grid of n_times
// common times (scan_candidate_pairs above). A pair of n common scans needs margins summing to
// R(n) = n − 2·least_hits[n] + 2 at the ends of its common span, so that fewer than least_hits[n]
// of its odd scans lie between them. by_length[l]: ⌈R(n)/2⌉ at most over n ≤ l, for a track of l
// scans (l up to the table's last; a track's pairs share at most l scans with it, and each end of
// the common span is an end of one of the two tracks). whole: ⌈R(n_times)/2⌉, for a track over every
// common time (its partners are either whole too, n = n_times, or lie inside it and carry their own
// margins), 0 when the table is shorter than n_times (no two whole tracks then pair).
struct InteriorMargins {
  std::vector<int32_t> by_length;
  int32_t whole = 0;
  // The margin of a track without gaps over `span` of the n_times common times.
  int32_t of(AlignedTracks::Span span, int32_t n_times) const {
    if (span.begin == 0 && span.end == n_times) return whole;
    const auto most = static_cast<int32_t>(by_length.size()) - 1;
    return by_length[std::min(span.end - span.begin, most)];
  }
};
InteriorMargins interior_skip_margins(std::span<const int32_t> least_hits, int32_t n_times);

// The same by the O(n_a·n_b·K) scan (the naive peer for tests).
CandidatePairs scan_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                              double radius_scale = 1.0);

}  // namespace trackassoc
