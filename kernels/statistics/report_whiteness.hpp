// Whether a sensor's reports have a filter's lag at all: the test that decides whether the
// two-sided alignment's manoeuvre-lag terms apply (AlignmentOptions::lag_inflation, lag_look_ahead,
// whiteness_threshold; kernels/statistics/association_statistic.cpp; docs/design.md §4.3). A
// constant-velocity Kalman filter lags an accelerating target: its position by â·τ², its velocity by
// â·τ, with τ² = P_pp/P_vv its steady-state lag time²; the aligned report's covariance is widened by
// that bias.
//
// The test (measure_report_whiteness). The lag is a property of a recursive estimator: its error
// carries over from report to report. Reports with independent errors (a measurement-level source,
// a simulator's noisy truth) have no lag, and for them the terms read each report's velocity noise
// as an acceleration held for τ: with the margin of 1.5 about one change in five of a steady track
// passes it, and on the scale study's tracks (P_pp/P_vv = 225 s²) 12 % of the track-scans grew to
// σ of kilometres (docs/performance.md, "Session 31"). The test is a whiteness test on the
// velocity's second difference over three consecutive reports at t₀ < t₁ < t₂, which cancels any
// constant acceleration (so a steady turn or a speed change does not read as noise):
//   e = v₂ − v₁ − r·(v₁ − v₀),   r = (t₂ − t₁)/(t₁ − t₀),
//   S = P_v,2 + (1 + r)²·P_v,1 + r²·P_v,0   (the covariance of e for independent errors),
//   ρ = |e|² / tr S.
// With independent Gaussian errors ρ has mean 1, and median med(χ²_m)/m when S is a multiple of I
// (m the spatial dimension: 0.455, 0.693, 0.789 for m = 1, 2, 3); as one axis comes to dominate S
// the median falls towards med(χ²₁) = 0.455. A filter's velocity error is smooth, so its ρ is far
// smaller: simulated CV Kalman filters, one axis, medians 0.004 (τ = 24 T), 0.038 (τ = 3 T), 0.096
// (τ = 1.3 T), 0.23 (τ = 0.6 T) against 0.455 for independent errors (T the report period). The
// median ρ over the sensor's tracks, divided by med(χ²_m)/m (so 1 for independent errors of an
// isotropic S), is compared with AlignmentOptions::whiteness_threshold (0.6): at or above it the
// sensor's reports are taken as independent and the lag terms are off for it.
// Why the trace, not eᵀS⁻¹e/m (exactly χ²_m/m for any S): a radar track's velocity is smooth
// across the line of sight, where its covariance is large, and whiter along it, where its range is
// measured well; the trace weighs the axes by their variance. Measured on the recorded family (100
// runs, seeds 1 and 2), the largest sensor median is 0.40 with the trace and 0.49 with eᵀS⁻¹e/m.
// The trace's price: independent errors with one dominant axis read 0.66 (m = 2) to 0.58 (m = 3)
// at the worst and may keep their lag terms, which is the behaviour before the test; a filter read
// as independent would lose them, which is the costlier mistake. A filter fast enough to be
// misread (τ below about 0.6 T in those simulations) lags by â·τ² < 0.36·â·T²; that this is small
// beside its own position error is argued, not measured.
// Fewer than kLeastTriples usable triples: the test cannot tell, and the lag terms stay on.
#pragma once

#include <cstddef>
#include <span>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

struct ReportWhiteness {
  double median_ratio = 0.0;  // the median ρ over the triples used, divided by med(χ²_m)/m
  std::size_t triples = 0;    // the usable triples tested (at most kMaxTriples)
  bool filtered = true;       // the lag terms apply (also when triples < kLeastTriples)
};
inline constexpr std::size_t kLeastTriples = 30;
// The median of 4 096 independent χ²₂/2 draws, relative to its own, has a standard error of 0.023
// (0.036 for m = 1); neighbouring triples share reports, so a sensor's sample is a little noisier.
inline constexpr std::size_t kMaxTriples = 4096;

// The test above over one sensor's tracks: `rows` its rows ordered by (track, time), `begin` the
// first of each track's (and rows.size() last). The triples are numbered over the tracks; all are
// tested when there are at most kMaxTriples, else kMaxTriples of them at the positions ⌊N·frac(j·φ)⌋,
// j < kMaxTriples (φ the golden ratio: a Weyl sequence, spread over the tracks whatever their
// lengths). A triple is used when its times ascend, 0.1 ≤ r ≤ 10, its velocity variances are ≥ 0
// with tr S > 0, and ρ is finite. O(tracks + kMaxTriples·log kMaxTriples) time, O(tracks + kMaxTriples)
// memory; serial and deterministic.
ReportWhiteness measure_report_whiteness(const TrackTable& tracks, std::span<const std::size_t> rows,
                                         std::span<const std::size_t> begin, const AlignmentOptions& options);

}  // namespace trackassoc
