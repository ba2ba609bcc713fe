// The 3-7-1 back-propagation network that tunes filter F2 of the parallel CS filters
// (seed 002 §1 and §3; docs/design.md §4.2).
//
// Network: 3 inputs, 7 logistic hidden units, 1 logistic output in (0, 1) (seed 002 §1: "3 input
// nodes, 7 hidden nodes, 1 output node ... a value in [0 1]"). Training: on-line back-propagation
// (Rumelhart, Hinton, Williams 1986) with momentum 0.9 and learning rate 0.7, 16 samples, 5000
// iterations (= epochs over the 16 samples in a fixed order), squared error E = ½ Σ (y − t)²
// (seed 002 §3; the paper reports a "total error" of 2.6·10⁻⁵ at the end without defining it; our
// designed pairs end at ½Σ = 1.9·10⁻⁴, i.e. a mean squared error (1/16)Σ(y − t)² = 2.4·10⁻⁵ —
// the paper's figure is most likely that mean). Initial weights U(−0.5, 0.5) from a
// CounterRng. Cost: O(iterations · samples · 3·7) — about a millisecond.
//
// Training pairs — not given in the paper, designed here:
//   Inputs are the normalised squared differences U1, U2, U3 of the two filters' predicted
//   position, velocity and acceleration (seed 002 Eqs. 3–5). Under "no manoeuvre" both filters
//   track the truth and each U is a ratio of a squared difference to a sum of variances, so it is
//   O(1) or below; at a manoeuvre onset the fast filter F1 runs away from F2 and the U grow large.
//   The network sees them squashed, u = U/(1+U) ∈ [0, 1), so that a logistic layer covers the whole
//   range without saturating.
//   The target output is the scale of F2's system variance:
//       t(Ū) = y_min + (1 − y_min) · Ū/(Ū + 1),   Ū = (U1 + U2 + U3)/3,   y_min = 0.05:
//   filters that agree (Ū → 0) shrink F2's variance twenty-fold (the accuracy of a non-manoeuvre
//   model), one-sigma disagreement (Ū = 1) halves it, a clear manoeuvre (Ū ≥ 9) keeps ≥ 90 %.
//   The 16 samples are 8 levels Ū ∈ {0, 0.1, 0.3, 0.6, 1, 2, 4, 10} in two patterns: isotropic
//   (Ū, Ū, Ū), and "kinematic" (0.5Ū, Ū, 1.5Ū) where the velocity and acceleration disagree more
//   than the position — how a manoeuvre onset looks to the two filters.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace trackassoc {

struct BpNetwork {
  static constexpr int kInputs = 3, kHidden = 7;
  std::array<std::array<double, kInputs + 1>, kHidden> w1{};  // hidden weights, last = bias
  std::array<double, kHidden + 1> w2{};                       // output weights, last = bias
  // Output in (0, 1) for raw inputs x (already squashed by the caller when needed).
  double evaluate(const std::array<double, kInputs>& x) const;
};

struct BpSample {
  std::array<double, 3> input;
  double target;
};

struct BpTrainingOptions {
  double learning_rate = 0.7;  // seed 002 §3
  double momentum = 0.9;       // seed 002 §3
  int iterations = 5000;       // seed 002 §3; one iteration = one pass over all samples
  uint64_t seed = 2001;        // initial weights
  void validate() const;       // throws InputError naming the field
};

struct BpTrainingSummary {
  double initial_error = 0.0;  // E = ½ Σ (y − t)² over the samples, before training
  double final_error = 0.0;    // after training
  double final_mse = 0.0;      // mean squared error (1/P) Σ (y − t)² after training
  int iterations = 0;
  double wall_time_s = 0.0;
};

BpTrainingSummary train_bp_network(BpNetwork& net, const std::vector<BpSample>& samples,
                                   const BpTrainingOptions& options);

// The 16 designed training pairs (inputs already squashed) described above.
std::vector<BpSample> cs_network_training_set();
// Squashes the raw normalised differences U_k of Eqs. 3–5: u = U/(1+U).
std::array<double, 3> cs_network_inputs(double u1, double u2, double u3);
// A network trained on cs_network_training_set() with the default options (deterministic).
BpNetwork trained_cs_network(BpTrainingSummary* summary = nullptr);

}  // namespace trackassoc
