// Batched Kalman filter banks: constant velocity (CV) and constant acceleration (CA), 2-D and 3-D
// (docs/design.md §4.2).
//
// Algorithm. The linear Kalman filter (Bar-Shalom, Li, Kirubarajan, "Estimation with Applications
// to Tracking and Navigation", 2001, §5.2.3) with a position measurement H = [I 0]:
//   predict  x ← F x,  P ← F P Fᵀ + Q
//   update   S = H P Hᵀ + R,  K = P Hᵀ S⁻¹,  x ← x + K (z − H x),  P ← P − K S Kᵀ
// A missed detection skips the update (the track coasts on its prediction).
// Models, per axis (F = F1 ⊗ I_d, Q = Q1 ⊗ I_d):
//   CV: F1 = [1 T; 0 1],  Q1 = σ² Γ Γᵀ, Γ = [T²/2, T]ᵀ         discrete white-noise acceleration
//                                                              (ibid. §6.3.2, Eq. 6.3.2-4)
//   CA: F1 = [1 T T²/2; 0 1 T; 0 0 1], Q1 = σ² Γ Γᵀ, Γ = [T²/2, T, 1]ᵀ   Wiener-sequence
//                                                              acceleration (ibid. §6.3.3, Eq. 6.3.3-4)
// σ is KalmanOptions::process_noise [m/s²].
//
// Layout. A bank of N tracks is a Matriplex (mkFit): blocks of 8 tracks, component c of lane l at
// block[c·8 + l], state first, then the packed upper triangle of P. State components are ordered
// by derivative block: x, y[, z], vx, vy[, vz][, ax, ay[, az]] — so a CV state is a prefix of a CA
// state (used by the IMM to mix models of different dimension). Measurements come in as plain SoA
// spans of length N in bank order.
//
// Complexity. One step costs O(N·D³/8) vector instructions and streams (D + D(D+1)/2)·8 bytes of
// state per track plus the measurement; the blocks are split across oneTBB with
// parallel_for_range (static partition, so results do not depend on the thread count).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace trackassoc {

inline constexpr int kBankLanes = 8;

// Tracks of one kinematic model: spatial dimension d (2 or 3), derivative order n (2 = position
// and velocity, 3 = plus acceleration), state dimension D = n·d.
class KinematicBank {
 public:
  KinematicBank() = default;
  // Tracks start at x = 0, P = I (padding lanes keep finite values).
  KinematicBank(int spatial_dim, int order, std::size_t tracks);

  int spatial_dim() const { return d_; }
  int order() const { return n_; }
  int dim() const { return d_ * n_; }
  std::size_t size() const { return size_; }
  std::size_t num_blocks() const { return (size_ + kBankLanes - 1) / kBankLanes; }
  std::size_t block_stride() const {
    return static_cast<std::size_t>(dim() + dim() * (dim() + 1) / 2) * kBankLanes;
  }
  double* block(std::size_t b) { return data_.data() + b * block_stride(); }
  const double* block(std::size_t b) const { return data_.data() + b * block_stride(); }

  // Element access (slow path: initialisation, output, tests).
  double state(std::size_t i, int c) const { return data_[offset(i, c)]; }
  void set_state(std::size_t i, int c, double v) { data_[offset(i, c)] = v; }
  double cov(std::size_t i, int r, int c) const { return data_[offset(i, dim() + packed(r, c))]; }
  void set_cov(std::size_t i, int r, int c, double v) { data_[offset(i, dim() + packed(r, c))] = v; }
  Eigen::VectorXd state_vector(std::size_t i) const;
  Eigen::MatrixXd covariance(std::size_t i) const;
  void set(std::size_t i, const Eigen::VectorXd& x, const Eigen::MatrixXd& P);

 private:
  int packed(int r, int c) const {
    if (r > c) std::swap(r, c);
    return r * dim() - r * (r - 1) / 2 + (c - r);
  }
  std::size_t offset(std::size_t i, int c) const {
    return (i / kBankLanes) * block_stride() + static_cast<std::size_t>(c) * kBankLanes + i % kBankLanes;
  }
  int d_ = 2, n_ = 2;
  std::size_t size_ = 0;
  std::vector<double> data_;
};

// The Cartesian (converted) position measurements of one scan, one entry per track in bank order.
// z[a] for a < d; R[k] the packed upper triangle of the d×d covariance (3 entries in 2-D, 6 in 3-D).
// detected[i] = 0 marks a missed detection (predict only); an empty span means all detected.
struct PositionScan {
  std::span<const double> z[3];
  std::span<const double> R[6];
  std::span<const uint8_t> detected;
};

// Optional per-track outputs: normalised innovation squared and Gaussian log-likelihood of the
// innovation (0 for missed detections). Leave a span empty to skip it.
struct InnovationOutput {
  std::span<double> nis;
  std::span<double> log_likelihood;
};

enum class KalmanModel { kConstantVelocity = 2, kConstantAcceleration = 3 };

struct KalmanOptions {
  KalmanModel model = KalmanModel::kConstantVelocity;
  double process_noise = 1.0;      // σ of the (white-noise / Wiener-sequence) acceleration [m/s²]
  std::size_t grain_blocks = 256;  // blocks of 8 tracks per TBB task, at least
  void validate() const;           // throws InputError naming the field
};

struct FilterStepSummary {
  std::size_t tracks = 0;   // tracks advanced
  std::size_t updated = 0;  // tracks with a detection (the rest coasted)
};

// Advances every track of `bank` by one scan of length dt [s] (> 0, or 0 for an update only):
// predict, then update the detected tracks. The bank's order must match options.model.
FilterStepSummary kalman_bank_step(KinematicBank& bank, double dt, const PositionScan& scan,
                                   const KalmanOptions& options, InnovationOutput out = {});

// The update half alone (any order): updates the detected tracks of `bank` with `scan`. Used by
// filters whose prediction is not a plain CV/CA model (CS, IMM).
FilterStepSummary kinematic_bank_update(KinematicBank& bank, const PositionScan& scan,
                                        InnovationOutput out = {}, std::size_t grain_blocks = 256);

// Per-axis transition F1 and process noise Q1 (n×n) of the CV (n = 2) and CA (n = 3) models above.
Eigen::MatrixXd kinematic_transition(int order, double dt);
Eigen::MatrixXd kinematic_process_noise(int order, double dt, double sigma);

// Two-point initialisation (Bar-Shalom et al. 2001, §5.5.3): x = [z2, (z2 − z1)/T],
// P = [[R2, R2/T], [R2/T, (R1 + R2)/T²]]; for order 3 the acceleration starts at 0 with variance
// accel_variance and no correlation. z and R are Cartesian position (d) and covariance (d×d).
void two_point_initialise(KinematicBank& bank, std::size_t i, const Eigen::VectorXd& z1,
                          const Eigen::MatrixXd& R1, const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2,
                          double dt, double accel_variance = 0.0);

}  // namespace trackassoc
