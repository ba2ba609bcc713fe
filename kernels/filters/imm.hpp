// Interacting multiple model (IMM) filter bank, batched, over models of different state
// dimension (seed 002 §2; docs/design.md §4.2).
//
// Algorithm (Blom & Bar-Shalom 1988; Bar-Shalom, Li, Kirubarajan 2001, §11.6.6; seed 002 Eqs. 6–9):
//   1. Mixing probabilities: c̄_j = Σ_i π_ij μ_i,  μ_{i|j} = π_ij μ_i / c̄_j           (Eq. 6)
//   2. Mixed initial conditions for each model j:
//        x0_j = Σ_i μ_{i|j} x̃_i^{(j)},  P0_j = Σ_i μ_{i|j} [P̃_i^{(j)} + (x̃_i − x0_j)(x̃_i − x0_j)ᵀ]  (Eq. 7)
//   3. Model-matched filtering (each model is a batched bank: CV/CA Kalman, CS, or the parallel
//      CS filters with the network), giving the innovation likelihoods Λ_j.
//   4. μ_j = Λ_j c̄_j / Σ_l Λ_l c̄_l                                                   (Eq. 9)
//   5. Combined estimate x = Σ_j μ_j x̃_j, P = Σ_j μ_j [P̃_j + (x̃_j − x)(x̃_j − x)ᵀ]      (Eq. 8)
// Unequal dimensions. All states share the derivative-block layout, so a CV state (x, v) is a
// prefix of a CA/CS state (x, v, a). x̃_i^{(j)} is model i's estimate seen in model j's space:
// truncated when model i is larger; when it is smaller, the missing components are taken from
// model j's own estimate with its own covariance block and no cross-covariance (the "unbiased
// mixing" of Granström, Willett, Bar-Shalom, "Systematic approach to IMM mixing for unequal
// dimension states", IEEE T-AES 51(4), 2015) — never zero-padding, which would bias the mixed
// acceleration towards 0. The combined estimate lives in the largest model's space, with the same
// extension (from the largest model). A missed detection gives Λ_j = 1 for all j (prediction only).
// With Π = I the models run independently and μ follows Bayes' rule; with μ0 = e_j the IMM is
// exactly model j.
// For the parallel CS model only F2 (the output filter) is mixed; F1 and the network run on.
// Complexity per scan: the model banks plus O(N·M²·D²) for mixing and combination.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "kernels/filters/cs_filter.hpp"
#include "kernels/filters/cs_parallel.hpp"
#include "kernels/filters/kalman_bank.hpp"
#include "kernels/learning/bp_network.hpp"

namespace trackassoc {

enum class ImmModelKind { kConstantVelocity, kConstantAcceleration, kCurrentStatistical, kCsParallel };

struct ImmModelSpec {
  ImmModelKind kind = ImmModelKind::kConstantVelocity;
  double process_noise = 1.0;     // σ [m/s²] of the CV / CA Kalman models
  CsOptions cs;                   // kCurrentStatistical
  CsParallelOptions cs_parallel;  // kCsParallel
  int order() const { return kind == ImmModelKind::kConstantVelocity ? 2 : 3; }
};

struct ImmOptions {
  std::vector<ImmModelSpec> models;
  std::vector<double> transition;             // M×M row-major, π_ij = P(model j now | model i before)
  std::vector<double> initial_probabilities;  // M, sums to 1
  std::size_t grain_blocks = 64;
  void validate() const;  // throws InputError naming the field
  // seed 002 §3: {CS-parallel with network, CA Kalman σ = 5 m/s²}, Π = [[0.97, 0.03], [0.03, 0.97]],
  // μ0 = (0.5, 0.5).
  static ImmOptions seed002();
};

struct ImmModel {
  ImmModelSpec spec;
  KinematicBank bank;                        // the mixed filter (unused for kCsParallel)
  std::unique_ptr<CsParallelBank> parallel;  // kCsParallel only; its f2 is the mixed filter
  KinematicBank& filter() { return parallel ? parallel->f2 : bank; }
  const KinematicBank& filter() const { return parallel ? parallel->f2 : bank; }
};

class ImmBank {
 public:
  // `network` is used by kCsParallel models (see trained_cs_network()).
  ImmBank(int spatial_dim, std::size_t tracks, const ImmOptions& options, const BpNetwork& network = {});
  std::size_t size() const { return n_; }
  int spatial_dim() const { return d_; }
  int num_models() const { return static_cast<int>(models_.size()); }
  const ImmOptions& options() const { return options_; }
  double probability(std::size_t i, int j) const { return mu_[j * n_ + i]; }
  ImmModel& model(int j) { return models_[j]; }
  const ImmModel& model(int j) const { return models_[j]; }
  const KinematicBank& combined() const { return combined_; }  // in the largest model's space
  // Two-point initialisation of track i in every model (acceleration prior variance for order 3),
  // probabilities reset to the initial ones.
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt, double accel_variance);

 private:
  friend FilterStepSummary imm_bank_step(ImmBank&, double, const PositionScan&, InnovationOutput);
  int d_;
  std::size_t n_;
  ImmOptions options_;
  std::vector<ImmModel> models_;
  std::vector<double> mu_, cbar_;        // M×N, model-major
  std::vector<std::vector<double>> ll_;  // per model, N log-likelihoods of the last scan
  KinematicBank combined_;
  int largest_ = 0;  // index of the first model of the largest order
};

// Advances every track one scan (mixing, model-matched filtering, probability update,
// combination). `out.log_likelihood` receives log Σ_j Λ_j c̄_j (the IMM's own likelihood).
FilterStepSummary imm_bank_step(ImmBank& bank, double dt, const PositionScan& scan,
                                InnovationOutput out = {});

}  // namespace trackassoc
