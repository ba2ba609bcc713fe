// The manoeuvre-lag terms of the two-sided alignment (AlignmentOptions::lag_inflation,
// lag_look_ahead, lag_noise_margin; docs/design.md §4.3, "Manoeuvre lag"), and the test that
// decides whether a sensor's reports have a filter's lag at all.
//
// Lag. A constant-velocity Kalman filter lags an accelerating target: its position by â·τ², its
// velocity by â·τ, with τ² = P_pp/P_vv its steady-state lag time² (read off its own covariance).
// The aligned report's covariance is widened by that bias (manoeuvre_lag).
//
// Whether the reports are a filter's output (sensor_reports_are_filtered). The lag is a property
// of a recursive estimator: its error carries over from report to report. Reports with independent
// errors (a measurement-level source, a simulator's noisy truth) have no lag, and for them the
// terms read each report's velocity noise as an acceleration held for τ: with the margin of 1.5
// about one change in five of a steady track passes it, and on the scale study's tracks (P_pp/P_vv =
// 225 s²) 12 % of the track-scans grew to σ of kilometres (docs/performance.md, "Session 31").
// The test is a whiteness test on the velocity's second difference over three consecutive reports
// at t₀ < t₁ < t₂, which cancels any constant acceleration (so a steady turn or a speed change
// does not read as noise):
//   e = v₂ − v₁ − r·(v₁ − v₀),   r = (t₂ − t₁)/(t₁ − t₀),
//   ρ = |e|² / tr(P_v,2 + (1 + r)²·P_v,1 + r²·P_v,0)   (the variance of e for independent errors).
// With independent errors ρ has mean 1 and median med(χ²_m)/m (m the spatial dimension: 0.455,
// 0.693, 0.789 for m = 1, 2, 3). A filter's velocity error is smooth, so its ρ is far smaller:
// simulated CV Kalman filters, one axis, medians 0.004 (τ = 24 T), 0.038 (τ = 3 T), 0.096
// (τ = 1.3 T), 0.23 (τ = 0.6 T) against 0.455 for independent errors (T the report period). The
// sensor's median ρ over its tracks, divided by med(χ²_m)/m, is compared with
// AlignmentOptions::unfiltered_ratio (0.6): at or above it the sensor's reports are taken as
// independent and the lag terms are off for it. A filter fast enough to be misread (τ < T) lags by
// â·τ² < â·T², which the alignment's process noise already covers, so the misreading costs little.
// Fewer than kLeastTriples usable triples: the test cannot tell, and the lag terms stay on.
#pragma once

#include <cstddef>
#include <span>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

struct ManoeuvreLag {
  double position_variance = 0.0, velocity_variance = 0.0;
};

// The lag variance added per axis to the report rows[pos] of a track whose rows (in time order) are
// rows[b, e). O(the track's reports within τ after it).
ManoeuvreLag manoeuvre_lag(const TrackTable& tracks, std::span<const std::size_t> rows, std::size_t b,
                           std::size_t e, std::size_t pos, const AlignmentOptions& options);

struct ReportWhiteness {
  double median_ratio = 0.0;  // the median ρ over the triples used, divided by med(χ²_m)/m
  std::size_t triples = 0;    // the usable triples tested (every stride-th, at most kMaxTriples)
  bool filtered = true;       // the lag terms apply (also when triples < kLeastTriples)
};
inline constexpr std::size_t kLeastTriples = 30;
inline constexpr std::size_t kMaxTriples = 4096;  // the median's standard error then ≈ 0.02

// The test above over one sensor's tracks: `rows` its rows ordered by (track, time), `begin` the
// first of each track's (and rows.size() last). The triples are numbered over the tracks and every
// stride-th is tested, stride = ⌈triples / kMaxTriples⌉; one is used when its three times are
// ascending, 0.1 ≤ r ≤ 10, and its noise variance is positive and finite. O(tracks + kMaxTriples)
// time and O(kMaxTriples) memory; the same answer for any thread count.
ReportWhiteness sensor_reports_are_filtered(const TrackTable& tracks, std::span<const std::size_t> rows,
                                            std::span<const std::size_t> begin,
                                            const AlignmentOptions& options);

}  // namespace trackassoc
