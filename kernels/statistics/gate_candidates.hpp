// The candidates of a gate, lossless (docs/design.md §4.3, "Sparse form"): which index serves which
// gate, and the two filters that drop, before λ, pairs the gate must reject, each from the gate's
// own bound on the position block:
//   * the count filter of the calibrated gate (least_scans_within_bound), applied inside the per-scan
//     index (kernels/statistics/scan_candidates.hpp) as it counts each pair's scans within its bound;
//   * the position-bound prune (prune_by_position_bound), on each pair the index keeps.
// The indexes themselves: kernels/statistics/scan_candidates.hpp (per scan, the calibrated gate) and
// kernels/statistics/sparse_candidates.hpp (time-averaged, seed 000's χ²(n·D) gate).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/scan_candidates.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// The count filter of the calibrated gate, least[n] for n = 0 … max_scans (empty when the gate
// is not kCalibrated, or when prune_by_position_bound passes pairs through unpruned). At a scan
// where a pair is not within its bound, |d_p|² > (tr P_a,pp + tr P_b,pp)·c, so its position term
// exceeds c and its capped term is c; a pair of n common scans within its bound at h of them
// has λ_c ≥ (n − h)·c, and the gate λ_c ≤ G(n) needs h ≥ n − G(n)/c (and h ≥ 1, the scan below the
// cap). least[n] is the smallest such h over n' ≥ n, so a lower bound of n may index it. Lossless:
// a pair it drops, prune_by_position_bound drops too (tests/kernels/statistics/
// test_scan_candidates_sensors.cpp). On the scale study's tracks at n = 1000 it keeps 6 % of the
// 473 k pairs found (docs/performance.md).
std::vector<int32_t> least_scans_within_bound(int dim, const StatisticOptions& statistic, int32_t max_scans);

// Drops the candidates that the gate must reject from their position components alone: the
// position block's term d_pᵀ C_pp⁻¹ d_p is at most the full dᵀC⁻¹d at every scan, so
// Σ min(term_p, c) ≤ λ_c; a pair whose bound already exceeds G(n) (or, for kCalibrated, with no
// scan below the cap) is out. O(pairs·K·m³) with m ≤ 3, against O(pairs·K·D³) for λ. Lossless;
// the correlated form is passed through unpruned. `gauge` (optional): the flags (a byte a pair) and
// the output (8 bytes a kept pair) are added before they are allocated, the flags released after.
CandidatePairs prune_by_position_bound(const AlignedTracks& a, const AlignedTracks& b,
                                       const CandidatePairs& pairs, const StatisticOptions& statistic,
                                       AllocationGauge* gauge = nullptr);

// The lossless candidate index for the gate of `statistic`: scan_candidate_pairs for kCalibrated,
// gated_candidate_pairs (the time-averaged bound of kernels/statistics/sparse_candidates.hpp) for
// kChiSquareSum. Every pair the gate can accept is returned
// (tests/engine/pipeline/test_sparse_sd_pipeline.cpp, ScanCandidates).
CandidatePairs candidate_pairs_for_gate(const AlignedTracks& a, const AlignedTracks& b,
                                        const StatisticOptions& statistic, double radius_scale = 1.0);
// The same for every pair s < t of `sensors` (slot s·S + t), through the multi-sensor index above
// with the count filter of least_scans_within_bound. `gauge` as for scan_candidate_pairs
// (kChiSquareSum: each slot's pairs are added once found); `found` (optional), per slot, the pairs
// the index found before the count filter.
std::vector<CandidatePairs> candidate_pairs_for_gate(std::span<const AlignedTracks* const> sensors,
                                                     const StatisticOptions& statistic,
                                                     double radius_scale = 1.0,
                                                     AllocationGauge* gauge = nullptr,
                                                     std::vector<std::size_t>* found = nullptr);

}  // namespace trackassoc
