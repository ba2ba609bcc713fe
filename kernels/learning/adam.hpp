// Adam optimiser (Kingma & Ba, "Adam: A method for stochastic optimization", ICLR 2015, Algorithm 1),
// with optional gradient clipping by global L2 norm (Pascanu et al. 2013), used for the BiLSTM.
//
//   g ← g·min(1, clip_norm/‖g‖)      (when clip_norm > 0)
//   m ← β1·m + (1−β1)·g,   v ← β2·v + (1−β2)·g²
//   θ ← θ − α·(m/(1−β1^k)) / (√(v/(1−β2^k)) + ε) − α·λ·θ
// The last term is decoupled weight decay (AdamW: Loshchilov & Hutter, "Decoupled weight decay
// regularization", ICLR 2019, Algorithm 2 with schedule multiplier 1), applied to every parameter;
// λ = 0 is plain Adam.
// O(P) per step for P parameters; serial, so bit-identical for any thread count.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace trackassoc {

struct AdamOptions {
  double learning_rate = 1e-3;  // α
  double beta1 = 0.9;           // β1 ∈ [0, 1)
  double beta2 = 0.999;         // β2 ∈ [0, 1)
  double epsilon = 1e-8;        // ε > 0
  double clip_norm = 5.0;       // clip the global gradient norm to this; 0 = no clipping
  double weight_decay = 0.0;    // λ ≥ 0, decoupled (AdamW); 0 = none
  void validate() const;        // throws InputError naming the field
};

template <class S>
struct AdamState {
  std::vector<S> m, v;  // first and second moment estimates
  int64_t step = 0;     // k
};

// One Adam step on `params` with gradient `grad` (same size). Returns the gradient norm before
// clipping. The state is sized on first use.
template <class S>
double adam_step(std::span<S> params, std::span<const S> grad, AdamState<S>& state,
                 const AdamOptions& options);

}  // namespace trackassoc
