// The "current" statistical (CS) model adaptive filter, batched (seed 002 §1; docs/design.md §4.2).
//
// Model (Zhou & Kumar, "A non-zero mean acceleration model ... for maneuvering targets", 1984;
// Singer, IEEE T-AES 6(4), 1970). Per axis the state is (position, velocity, acceleration); the
// acceleration is a first-order Markov process with manoeuvre frequency α around the "current"
// mean ā:
//   x(k+1) = Φ x(k) + U ā + w(k),   Φ = [[1, T, (αT−1+e^{−αT})/α²], [0, 1, (1−e^{−αT})/α], [0, 0, e^{−αT}]]
//   Q = σ_w² q(α, T)  with Singer's q_ij (Singer 1970, Eq. 19) and
//   σ_w² = 2 α σ_a²                                          (seed 002 Eq. 1)
//   σ_a² = (4−π)/π · (a_max − ā)²     for ā ≥ 0
//   σ_a² = (4−π)/π · (a_−max − ā)²    for ā < 0             (seed 002 Eq. 2, with the square that
//                                                             the seed as printed omits; docs/design.md §4.2)
// The mean ā is the predicted acceleration: ā = â(k|k) per axis (Zhou & Kumar's choice), so the
// state prediction Φ x̂ + U ā reduces to the CA prediction (p + vT + âT²/2, v + âT, â) while the
// covariance propagates with Φ: P ← Φ P Φᵀ + Q. Update: position measurement, as the Kalman bank.
// An optional per-track noise scale multiplies Q (used by F2 of the parallel filter, seed 002 §1).
//
// Layout: a KinematicBank of order 3 (x, y[, z], vx, vy[, vz], ax, ay[, az]) in Matriplex blocks.
// Complexity O(N·D³/8) vector operations per step; blocks split across oneTBB (deterministic).
#pragma once

#include <Eigen/Core>
#include <span>

#include "kernels/filters/kalman_bank.hpp"

namespace trackassoc {

struct CsOptions {
  double manoeuvre_frequency = 0.1;  // α [1/s], reciprocal of the manoeuvre time constant
  double a_max = 50.0;               // largest positive acceleration [m/s²]
  double a_neg_max = -50.0;          // largest negative acceleration a_−max [m/s²]
  double min_accel_variance = 1e-2;  // floor on σ_a² [m²/s⁴], keeps Q > 0 when ā reaches a_max
  std::size_t grain_blocks = 128;    // blocks of 8 tracks per TBB task, at least
  void validate() const;             // throws InputError naming the field
};

// σ_a² of seed 002 Eq. 2 (with the square) for the mean acceleration ā, floored.
double cs_accel_variance(double mean_accel, const CsOptions& options);

// Φ (3×3) and Singer's normalised q (3×3, to be multiplied by σ_w² = 2ασ_a²) for step T.
Eigen::Matrix3d cs_transition(double alpha, double dt);
Eigen::Matrix3d cs_process_noise_shape(double alpha, double dt);

// Advances all tracks of an order-3 bank by one scan: adaptive CS prediction, then the position
// update of the detected tracks. noise_scale (empty = 1) multiplies each track's Q.
FilterStepSummary cs_bank_step(KinematicBank& bank, double dt, const PositionScan& scan,
                               const CsOptions& options, std::span<const double> noise_scale = {},
                               InnovationOutput out = {});

}  // namespace trackassoc
