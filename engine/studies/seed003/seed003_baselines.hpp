// The classical baselines of seed 003 §3.1 for asynchronous two-radar tracks of converted plots:
// the weighted statistical test (Singer & Kanyuch 1970, seed 003 ref. [3]) and nearest neighbour
// (Singer & Kanyuch 1971, ref. [5]). As the paper describes them (§3.2: "they only look at the
// current time"), both compare the tracks at ONE time, the last plot of the radar-2 track, after
// time alignment of the radar-1 track (linear interpolation between its bracketing plots, or linear
// extrapolation from its last two plots) — the alignment seed 003 avoids.
//
// Weighted test: d = z2 − ẑ1, C = R2 + w²·R1a + (1−w)²·R1b (independent plot errors; w the
// interpolation weight, outside [0, 1] when extrapolating), λ = dᵀC⁻¹d ~ χ²(2) for the same target.
// R is the converted-measurement covariance J·diag(σr², σθ²)·Jᵀ of a plot at (r, θ) from its radar.
// Association: 2-D LAP on λ, pairs with λ > χ²₂(gate) forbidden, tracks may stay unassigned.
// Nearest neighbour: each radar-1 track takes the radar-2 track at the smallest Euclidean distance
// at that time (not one-to-one, as in the classical NN), within `nn_gate` metres.
// Cost: O(N1·N2·log n) per scene.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/learning/siamese.hpp"

namespace trackassoc {

struct RadarErrorModel {
  double x = 0.0, y = 0.0;            // radar position [m]
  double sigma_range = 100.0;         // [m]
  double sigma_bearing = 0.01745329;  // [rad]
};

struct ClassicalBaselineOptions {
  RadarErrorModel radar1, radar2;
  double gate_probability = 0.99;  // weighted test: χ²(2) gate
  double nn_gate = 10000.0;        // nearest neighbour: largest distance [m]
  void validate() const;
};

// λ of every radar-1 × radar-2 pair (row-major) at the last radar-2 plot time.
std::vector<double> weighted_statistic_matrix(const TrackSequences& radar1, const TrackSequences& radar2,
                                              const ClassicalBaselineOptions& options);

// λ of listed pairs (pair classification on the seed 003 data set: same target iff λ ≤ gate).
std::vector<double> weighted_statistic_pairs(const TrackSequences& radar1, const TrackSequences& radar2,
                                             const PairSet& pairs, const ClassicalBaselineOptions& options);

std::vector<int32_t> associate_weighted_test(const TrackSequences& radar1, const TrackSequences& radar2,
                                             const ClassicalBaselineOptions& options);
std::vector<int32_t> associate_nearest_neighbour(const TrackSequences& radar1, const TrackSequences& radar2,
                                                 const ClassicalBaselineOptions& options);

}  // namespace trackassoc
