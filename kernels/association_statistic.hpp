// Track-to-track association statistics (seed 000 §2 Eq. 1–2; Bar-Shalom & Campo 1986).
//
// Local tracks of one sensor are first resampled at common times (asynchronous sensors: each
// track's latest estimate at or before the common time is predicted forward with a
// constant-velocity model, DESIGN §4.3). For a pair of tracks a (sensor s) and b (sensor t), the
// independent sequential statistic accumulates over the common times k where both exist:
//
//   λ(k) = λ(k−1) + dᵀ C⁻¹ d,   d = x̂_a(k) − x̂_b(k),   C = P_a + P_b              (Eq. 1–2)
//
// and the correlated-error variant uses C = P_a + P_b − P_ab − P_ba (Bar-Shalom–Campo), with the
// cross-covariance approximated as P_ab = ρ·(P_a^{1/2} P_b^{1/2}) for a user-chosen ρ, using the
// principal (symmetric) square roots, so that C = (1−ρ)(P_a + P_b) + ρ(P_a^{1/2} − P_b^{1/2})² stays
// SPD for 0 ≤ ρ < 1. Alignment uses continuous white-noise acceleration (details in the .cpp).
// Under H0 (same target) λ is chi-square with D·k degrees of freedom; a pair whose λ exceeds the
// chi-square quantile at the gate probability is not a candidate.
//
// Complexity: O(n_a · n_b · K · D³) for K common times; the pair loop is split across TBB.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/types.hpp"

namespace trackassoc {

// Tracks of one sensor at common times, SoA: state[(track·K + k)·D + c], cov likewise with the
// packed triangle, valid[track·K + k] = 1 when the track exists at common time k.
struct AlignedTracks {
  int32_t sensor = 0;
  int32_t dim = 4;  // D
  int32_t n_times = 0;
  std::vector<int32_t> track;  // local track number of each row
  std::vector<int32_t> truth;  // truth id of each row (-1 unknown)
  std::vector<double> state;
  std::vector<double> cov;
  std::vector<uint8_t> valid;
  int32_t n_tracks() const { return static_cast<int32_t>(track.size()); }
};

struct AlignmentOptions {
  // White-noise acceleration σ [m/s²] of the CV model used to predict a track's latest estimate
  // to the common time. 0 predicts the covariance without process noise.
  double process_noise = 1.0;
  // A track is valid at a common time only if its latest report is at most this old [s].
  double max_extrapolation = 10.0;
  void validate() const;
};

// Resamples the tracks of `sensor` in `tracks` at `common_times` (ascending).
AlignedTracks align_tracks(const TrackTable& tracks, int32_t sensor, std::span<const double> common_times,
                           const AlignmentOptions& options);

struct StatisticOptions {
  bool correlated = false;         // Bar-Shalom–Campo correlated-error form
  double cross_correlation = 0.0;  // ρ in [0, 1) for the correlated form
  double gate_probability = 0.99;  // chi-square gate; 1.0 disables gating
  void validate() const;
};

// λ for every pair (a, b): lambda[a·n_b + b], with its degrees of freedom and the gate decision.
struct PairStatistic {
  int32_t n_a = 0, n_b = 0;
  std::vector<double> lambda;
  std::vector<int32_t> dof;      // D · (number of common times); 0 when never together
  std::vector<uint8_t> in_gate;  // 1 when the pair is a candidate
};

PairStatistic independent_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                               const StatisticOptions& options);

// Chi-square quantile: the x with P(χ²_dof ≤ x) = p (Wilson–Hilferty start, Newton refinement).
double chi_square_quantile(double p, int dof);

}  // namespace trackassoc
