// Bidirectional LSTM over a batch of variable-length, padded and masked sequences: forward pass
// and back-propagation through time (BPTT), written by hand with Eigen.
//
// Algorithm: the LSTM cell of Hochreiter & Schmidhuber (1997) with a forget gate (Gers et al. 2000),
// without peepholes, as in PyTorch's nn.LSTM; gate order i, f, g, o:
//   a_t = Wx·x_t + Wh·h_{t−1} + b                        (4H)
//   i = σ(a_i), f = σ(a_f), g = tanh(a_g), o = σ(a_o)
//   c̃_t = f⊙c_{t−1} + i⊙g,   h̃_t = o⊙tanh(c̃_t)
// The bidirectional form runs a second, independently weighted LSTM from the last step to the first
// (Graves & Schmidhuber 2005, seed 003 ref. [15]); the sequence embedding is [h_fwd(end); h_bwd(start)]
// (2H), the "1×128 feature vector" of seed 003 Algorithm 1 Step 2 for H = 64.
//
// Masking (seed 003 Algorithm 1 Step 1 pads a pair to its longest length; the paper does not say what
// the network does with the padding). Here a padded step leaves the state unchanged:
//   h_t = m_t·h̃_t + (1−m_t)·h_{t−1},   c_t = m_t·c̃_t + (1−m_t)·c_{t−1},   m_t ∈ {0, 1}.
// The forward direction therefore ends holding the state of the last valid step, and the backward
// direction crosses the trailing padding with its zero initial state untouched, so the embedding is
// exactly independent of the amount of padding and of the padded values
// (tests/kernels/learning/test_bilstm.cpp). Padding must be trailing (valid steps first), which SequenceBatch
// guarantees.
//
// Complexity: forward O(T·B·4H·(F+H)), backward about twice that; memory O(T·B·4H) for the cache.
// Templated on the scalar: double for the gradient checks, float for training.
#pragma once

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <cstdint>
#include <vector>

namespace trackassoc {

template <class S>
using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
// Parameter and gradient buffers. Eigen vectorises with peeling that depends on the runtime
// alignment of a Map's address, and the peeled and vectorised paths may round differently; with
// every buffer aligned to Eigen's boundary, every run takes the same path (bit-identical results).
template <class S>
using AlignedVector = std::vector<S, Eigen::aligned_allocator<S>>;

// A batch of B sequences of F features, padded to the longest length T. steps[t] is F×B;
// mask(t, b) = 1 where step t of sequence b is valid, 0 where it is padding. Valid steps of every
// sequence come first (trailing padding). Every sequence has at least one valid step.
template <class S>
struct SequenceBatch {
  std::vector<MatrixX<S>> steps;
  MatrixX<S> mask;  // T×B
  int length() const { return static_cast<int>(steps.size()); }
  int batch() const { return static_cast<int>(mask.cols()); }
  int features() const { return steps.empty() ? 0 : static_cast<int>(steps[0].rows()); }
};

// Sizes of one LSTM direction. Parameters of one direction, flat and column-major:
// Wx (4H×F), then Wh (4H×H), then b (4H).
struct LstmShape {
  int input = 3;    // F
  int hidden = 64;  // H
  int64_t parameter_count() const { return 4LL * hidden * input + 4LL * hidden * hidden + 4LL * hidden; }
};

// What the forward pass keeps for BPTT, for one direction, in processing order (step index s is
// time t = s forward, t = T−1−s backward). gates[s] holds the activated (i, f, g, o), 4H×B;
// c[s], h[s] the masked state after step s; c_tanh[s] = tanh(c̃_s).
template <class S>
struct LstmCache {
  std::vector<MatrixX<S>> gates, c, h, c_tanh;
};

template <class S>
struct BiLstmCache {
  LstmCache<S> forward, backward;
};

// One LSTM direction. `params` points at parameter_count() scalars. `reverse` runs from T−1 to 0.
// Writes the final state (H×B) and fills `cache` when it is not null.
template <class S>
void lstm_forward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, bool reverse,
                  MatrixX<S>& h_final, LstmCache<S>* cache);

// BPTT for one direction, given dL/dh_final (H×B). Adds dL/dθ into `grad` (parameter_count()
// scalars, accumulated, not overwritten).
template <class S>
void lstm_backward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, bool reverse,
                   const LstmCache<S>& cache, const MatrixX<S>& dh_final, S* grad);

// BiLSTM: parameters [forward direction | backward direction], 2·LstmShape::parameter_count().
// embedding is 2H×B: rows [0, H) the forward final state, rows [H, 2H) the backward final state.
template <class S>
void bilstm_forward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x, MatrixX<S>& embedding,
                    BiLstmCache<S>* cache);

template <class S>
void bilstm_backward(const S* params, const LstmShape& shape, const SequenceBatch<S>& x,
                     const BiLstmCache<S>& cache, const MatrixX<S>& d_embedding, S* grad);

}  // namespace trackassoc
