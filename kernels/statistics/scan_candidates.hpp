// Candidate pairs for the calibrated gate, from a spatial index per common time (docs/design.md §4.3,
// "Sparse form"; kernels/statistics/association_statistic.hpp, GateMethod::kCalibrated).
//
// The calibrated gate accepts a pair only if at least one common scan k has a term
// dᵀC⁻¹d ≤ c (the per-scan cap). That gives a lossless spatial bound per scan:
//   dᵀC⁻¹d ≥ d_pᵀ C_pp⁻¹ d_p ≥ |d_p|² / μ_max(C_pp),   μ_max(C_pp) ≤ tr P_a,pp + tr P_b,pp,
// (a marginal Mahalanobis distance is at most the full one; the largest eigenvalue of a sum is at
// most the sum of the traces), so a pair with |d_p(k)|² > (tr P_a,pp(k) + tr P_b,pp(k))·c at every
// common scan cannot pass the gate. The bound is per scan, so it holds for any pattern of validity
// (late starts, early ends, asynchronous coverage), unlike a bound on time-averaged positions.
//
// Index: for each common time k, a uniform grid of cell size R_k = √((max tr_a + max tr_b)·c)
// over sensor b's valid positions (sorted by cell); each valid track of sensor a looks at its 3^m
// neighbouring cells and keeps the b whose own bound holds. Pairs are collected per scan
// (parallel over scans, TBB), then sorted and deduplicated, so the output does not depend on the
// thread count.
// Each scan indexes only the tracks valid there, listed from their spans (O(Σ spans + K)).
// Complexity: O(Σ_k (n_a(k) + n_b(k))·log n_b(k) + 3^m·Σ_k n_a(k)·log n_b(k) + hits) time, n_x(k) the
// tracks valid at scan k; O(Σ spans + hits) memory.
#pragma once

#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// `cap`: the per-scan cap c of the gate (SequentialGate::cap()); radius_scale ≥ 1 widens the bound.
CandidatePairs scan_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                    double radius_scale = 1.0);

// The same by the O(n_a·n_b·K) scan (the naive peer for tests).
CandidatePairs scan_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                              double radius_scale = 1.0);

// Drops the candidates that the gate must reject from their position components alone: the
// position block's term d_pᵀ C_pp⁻¹ d_p is at most the full dᵀC⁻¹d at every scan, so
// Σ min(term_p, c) ≤ λ_c; a pair whose bound already exceeds G(n) (or, for kCalibrated, with no
// scan below the cap) is out. O(pairs·K·m³) with m ≤ 3, against O(pairs·K·D³) for λ. Lossless;
// the correlated form is passed through unpruned.
CandidatePairs prune_by_position_bound(const AlignedTracks& a, const AlignedTracks& b,
                                       const CandidatePairs& pairs, const StatisticOptions& statistic);

// The lossless candidate index for the gate of `statistic`: scan_candidate_pairs for kCalibrated,
// gated_candidate_pairs (the time-averaged bound of kernels/statistics/sparse_candidates.hpp) for
// kChiSquareSum. Every pair the gate can accept is returned (tests/test_scan_candidates.cpp).
CandidatePairs candidate_pairs_for_gate(const AlignedTracks& a, const AlignedTracks& b,
                                        const StatisticOptions& statistic, double radius_scale = 1.0);

}  // namespace trackassoc
