// The diagonal schedule of the discrete 3-D Hopfield network (docs/design.md §4.4 "Schedules").
//
// Block (a, b) is the set of n1 neurons {(i, (i+a) mod n2, (i+b) mod n3) : i < n1}. Its
// neurons share no plane (distinct i, distinct j, distinct k), so for the full-plane energy
// without the D term (kernels/hopfield/hopfield_energy.hpp) the net input of one does not depend on the
// others: updating the whole block at once is exactly n1 asynchronous updates of seed 000
// Eq. 10, in any order, and never raises the energy. A sweep visits the n2·n3 blocks in a given
// order (a fresh random permutation per sweep in the solver); the blocks partition the n1n2n3
// neurons. Needs n1 ≤ n2 and n1 ≤ n3.
//
// Layout (why it is fast): the cost is re-laid out once per solve in block-major order,
// D[(a·n3 + b)·n1 + i] = ĉ(i, (i+a) mod n2, (i+b) mod n3) (DiagonalCost, shared read-only by all
// restarts), and each restart keeps its state in the same order, so a block is one contiguous
// run of cost and state. The plane sums R_i, S_j, T_k are small integers held in float. R is read
// at i, S at (i+a) mod n2 and T at (i+b) mod n3: to read the rotated S and T as one contiguous
// window without wrap-around segments, S and T are kept as three consecutive copies
// (S_ext[n2 + x] = S[x mod n2] on the window that blocks read), and every update writes the copy
// it read and the copies n2 before and after it. The block then runs as kDiagonalLanes-wide
// vector steps (GCC/Clang vector extensions: portable, AVX-512 or AVX2 or SSE as compiled); when
// L does not divide n1, one step covers the last L neurons first and the overlapping full step
// keeps the lanes already done unchanged, which is exact. The next blocks' cost and state are prefetched (the
// block order is random). Blocks with n1 < kDiagonalLanes run a scalar loop over the (at most three)
// wrap-free segments of the block — the original implementation, kept as sweep_reference(), which tests
// compare the vector path against neuron for neuron.
//
// Complexity: O(n1n2n3) per sweep, O(n1n2n3) memory for the layout (once) and per restart
// (state, uint8). The layout itself is O(n1n2n3), parallel over a.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "kernels/hopfield/hopfield_energy.hpp"

namespace trackassoc {

// The vector width (floats) of the diagonal block update.
inline constexpr int32_t kDiagonalLanes = 16;

// ĉ in the diagonal schedule's block-major layout. Throws InputError unless n1 ≤ n2, n3.
struct DiagonalCost {
  int32_t n1 = 0, n2 = 0, n3 = 0;
  std::vector<float> c;  // [(a·n3 + b)·n1 + i] = ĉ(i, (i+a) mod n2, (i+b) mod n3)
  explicit DiagonalCost(const NormalisedCost& cost);
  std::size_t num_blocks() const { return static_cast<std::size_t>(n2) * n3; }
  // Standard-layout index (i·n2 + j)·n3 + k of element i of block (a, b).
  std::size_t standard_index(int32_t a, int32_t b, int32_t i) const;
};

// One restart's state of the diagonal schedule (full-plane energy, D = 0).
class DiagonalNetwork {
 public:
  // Throws InputError unless w.D == 0. The first form shares a layout built once per solve; the
  // second builds its own.
  DiagonalNetwork(const HopfieldWeights& w, std::shared_ptr<const DiagonalCost> cost);
  DiagonalNetwork(const HopfieldWeights& w, const NormalisedCost& c);
  void set_state(std::span<const uint8_t> V);  // V in the standard (i, j, k) layout
  void get_state(std::span<uint8_t> V) const;  // back to the standard layout
  std::size_t num_blocks() const { return cost_->num_blocks(); }
  std::size_t standard_index(int32_t a, int32_t b, int32_t i) const { return cost_->standard_index(a, b, i); }
  // One sweep over the blocks in `block_order` (block = a·n3 + b). Returns the number of flips.
  int64_t sweep(std::span<const uint32_t> block_order);
  // The same sweep by the scalar segment loop (the reference the vector path must equal).
  int64_t sweep_reference(std::span<const uint32_t> block_order);
  void set_E(float E) { w_.E = E; }
  const HopfieldWeights& weights() const { return w_; }

 private:
  int64_t update_block_scalar(int32_t a, int32_t b);
  void recompute_sums();
  std::shared_ptr<const DiagonalCost> cost_;
  HopfieldWeights w_;
  int32_t n1_, n2_, n3_;
  std::vector<uint8_t> V_;    // state in block-major layout
  std::vector<float> R_;      // plane sums as exact small integers
  std::vector<float> S_, T_;  // three copies each: S_[n2 + x] = S[x mod n2] (see the header comment)
};

}  // namespace trackassoc
