// The per-scan bound of the calibrated gate on a pair's position block (docs/design.md §4.3,
// "Candidates"), as the per-scan candidate index (kernels/statistics/scan_candidates.hpp) tests
// it: a pair is within its bound at a scan when
//   |d_p|² ≤ (s_a + s_b)·c          (the circle, cheap), and
//   d_pᵀ (P_a + P_b)⁻¹ d_p ≤ c       (the ellipse inside it, by its adjugate: a superset, by a
//                                     relative 10⁻⁹, of the prune's Cholesky test,
//                                     kernels/statistics/gate_candidates.cpp),
// d_p the difference of the positions, P the position blocks (the first m ≤ 3 components of the
// state), s = position_spread(P) a bound on the largest eigenvalue of each. The circle holds the
// ellipse since d_pᵀC⁻¹d_p ≥ |d_p|²/μ_max(C) and μ_max(P_a + P_b) ≤ μ_max(P_a) + μ_max(P_b); it sets
// each track's search ball, of radius √(2·s·c). On elongated radar covariances the ellipse holds a
// small part of the circle's pairs.
#pragma once

#include <cstdint>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

// A position block packed as its upper triangle by rows, in at most kPositionBlock doubles: m = 2
// (xx, xy, yy), m = 3 (xx, xy, xz, yy, yz, zz); copied out of a packed covariance of dimension D.
inline constexpr int kPositionBlock = 6;
void position_block(const double* packed, int D, int m, double* out);

// A bound on the largest eigenvalue of a position block, by a relative 10⁻⁸ more so that the circle
// is never inside the ellipse's 10⁻⁹: its largest Gershgorin row sum P_ii + Σ_{j≠i} |P_ij| (a bound
// for any symmetric block), or its trace when that is smaller and the block is positive
// semi-definite (every principal minor ≥ 0: only then is the trace a bound; a block that is not,
// beside a larger one, can still sum to a positive definite C); m = 1: the variance. A NaN entry
// gives the trace (a NaN on the diagonal, NaN: never within; elsewhere the ellipse test passes the
// pair to the statistic, which reports it). The trace alone is m times the largest eigenvalue for
// an isotropic covariance: in 3-D the search radius √3 and the searched volume 5.2 times too large
// (the scale study's tracks, σ = 150 m on every axis, docs/performance.md "Session 33").
double position_spread(const double* block, int m);

// The bound for positions xa, xb (m coordinates), spreads sa, sb and position blocks pa, pb;
// c2 the per-scan cap c (times radius_scale²). True when P_a + P_b is not positive definite (as the
// prune decides: the statistic then reports it).
bool within_points(const double* xa, double sa, const double* pa, const double* xb, double sb,
                   const double* pb, int m, double c2);

// The same for track cells ca of a and cb of b (valid, same common time).
bool within_scan_bound(const AlignedTracks& a, int64_t ca, const AlignedTracks& b, int64_t cb, int m,
                       double c2);

}  // namespace trackassoc
