// Track-to-track fusion: the fused estimate of N local estimates (x_i, P_i) of one target at one
// time, after association (MATLAB trackFuser, Stone Soup #179). Three rules:
//
//  * naive — independent errors, information-weighted (the "simple convex combination" when the
//    cross-covariances are ignored; Bar-Shalom, Willett, Tian 2011, §9.1):
//        P = (Σ_i P_i⁻¹)⁻¹,   x = P Σ_i P_i⁻¹ x_i.
//    Overconfident when the errors are correlated (common process noise, common prior).
//
//  * Bar-Shalom–Campo — two tracks with the cross-covariance P_12 = E[e_1 e_2ᵀ] (Bar-Shalom &
//    Campo, "The effect of the common process noise on the two-sensor fused-track covariance",
//    IEEE T-AES 22(6), 1986, Eq. 9–10):
//        U = P_1 + P_2 − P_12 − P_21,   P_21 = P_12ᵀ
//        x = x_1 + (P_1 − P_12) U⁻¹ (x_2 − x_1)
//        P = P_1 − (P_1 − P_12) U⁻¹ (P_1 − P_21).
//    With P_12 = 0 it is the naive rule. For N tracks the same estimator is the best linear
//    unbiased one with the joint error covariance Σ (N·D × N·D, blocks P_ij), H = [I; …; I]:
//        P = (Hᵀ Σ⁻¹ H)⁻¹,   x = P Hᵀ Σ⁻¹ [x_1; …; x_N]         (fuse_with_cross_covariance)
//    which is Eq. 9–10 for N = 2 (Chong, Mori, Chang 1990; Bar-Shalom, Li, Kirubarajan 2001 §8.4).
//
//  * covariance intersection — unknown correlation (Julier & Uhlmann, "A non-divergent estimation
//    algorithm in the presence of unknown correlations", ACC 1997, Eq. 6–7):
//        P⁻¹ = Σ_i ω_i P_i⁻¹,   x = P Σ_i ω_i P_i⁻¹ x_i,   ω_i ≥ 0, Σ_i ω_i = 1,
//    with ω minimising tr P or det P. P is consistent (P ≥ the actual error covariance) for every
//    cross-covariance, hence never below the Bar-Shalom–Campo P with the true one in the trace
//    sense; identical inputs give the input back. Both criteria are convex in ω (tr M⁻¹ and
//    −log det M are convex on SPD M, and M = Σ ω_i P_i⁻¹ is affine in ω), so for N = 2 a golden-
//    section search over ω ∈ [0, 1] finds the optimum; for N > 2, two-coordinate descent with the
//    maximal violating pair (SMO: move weight from the ω_j > 0 with the largest ∂J/∂ω to the ω_i
//    with the smallest, by golden section) until that gradient gap, the KKT condition of the
//    simplex, is below the tolerance.
//
// Complexity per call: naive O(N·D³); Bar-Shalom–Campo O(D³), the joint form O((N·D)³); CI
// O(S·(N + G)·D³) for S pair steps (N > 2; 1 for N = 2) and G golden-section steps (G ≈ 45 at the
// default tolerance).
// Inputs are checked: equal sizes, symmetric positive definite P_i and U (or Σ); an InputError
// names the matrix otherwise. No state, no threads: callers fuse many (tuple, time) cells in
// parallel.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class FusionRule { kNaive, kBarShalomCampo, kCovarianceIntersection };
inline constexpr EnumName<FusionRule> kFusionRuleNames[]{
    {FusionRule::kNaive, "naive", "independent errors"},
    {FusionRule::kBarShalomCampo, "bsc", "Bar-Shalom–Campo"},
    {FusionRule::kCovarianceIntersection, "ci", "covariance intersection"}};
constexpr std::span<const EnumName<FusionRule>> enum_names(FusionRule) { return kFusionRuleNames; }

enum class CiCriterion { kTrace, kDeterminant };
inline constexpr EnumName<CiCriterion> kCiCriterionNames[]{{CiCriterion::kTrace, "trace"},
                                                           {CiCriterion::kDeterminant, "det"}};
constexpr std::span<const EnumName<CiCriterion>> enum_names(CiCriterion) { return kCiCriterionNames; }

struct CiOptions {
  CiCriterion criterion = CiCriterion::kTrace;
  double tolerance = 1e-9;  // the golden-section interval on ω; N > 2: the gradient gap that stops
  int max_sweeps = 200;     // N > 2: at most max_sweeps·N pair steps
  void validate() const;
};

struct FusedEstimate {
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  std::vector<double> omega;  // CI: the weights ω_i (sum 1); empty for the other rules
  int sweeps = 0;             // CI, N > 2: pair steps run (0 for N ≤ 2)
};

// Information-weighted fusion of N ≥ 1 estimates with independent errors.
FusedEstimate fuse_naive(std::span<const Eigen::VectorXd> x, std::span<const Eigen::MatrixXd> P);

// Bar-Shalom–Campo Eq. 9–10 for two estimates with cross-covariance P12 = E[e1 e2ᵀ].
FusedEstimate fuse_bar_shalom_campo(const Eigen::VectorXd& x1, const Eigen::MatrixXd& P1,
                                    const Eigen::VectorXd& x2, const Eigen::MatrixXd& P2,
                                    const Eigen::MatrixXd& P12);

// The BLUE of N ≥ 1 estimates with the joint error covariance `joint` (N·D × N·D, block (i, j) =
// E[e_i e_jᵀ]); Bar-Shalom–Campo for N = 2.
FusedEstimate fuse_with_cross_covariance(std::span<const Eigen::VectorXd> x, const Eigen::MatrixXd& joint);

// Covariance intersection of N ≥ 1 estimates, ω by options.criterion.
FusedEstimate fuse_covariance_intersection(std::span<const Eigen::VectorXd> x,
                                           std::span<const Eigen::MatrixXd> P, const CiOptions& options);

// The CI criterion at weights ω: tr P(ω) or det P(ω), P(ω) = (Σ ω_i P_i⁻¹)⁻¹ (for tests and studies).
double ci_criterion_value(std::span<const Eigen::MatrixXd> P, std::span<const double> omega,
                          CiCriterion criterion);

}  // namespace trackassoc
