// The continuous Hopfield network (CHNN) for the 3-D assignment (seed 004 §1–2; Hopfield & Tank,
// "Neural computation of decisions in optimization problems", Biol. Cybern. 52 (1985) 141–152).
//
// Seed 004's Eqs. 5, 6, 8, 10 and 11 were lost in the text, so the standard Hopfield–Tank form is
// used with the paper's description of each term (docs/design.md §4.4): the full-plane energy of
// kernels/hopfield/hopfield_energy.hpp with continuous V ∈ (0, 1),
//   E(V) = A/2·Σ_i(R_i−1)² + B/2·Σ_j(S_j−1)² + C/2·Σ_k(T_k−1)² + D/2·(M−N)² + E·Σ ĉ V,
// the net input h = −∂E/∂V_ijk = −[A(R_i−1) + B(S_j−1) + C(T_k−1) + D(M−N) + E·ĉ_ijk], and
//   du/dt = −u/τ + h,   V = ½(1 + tanh(u/u₀)),
// integrated by explicit Euler steps of size dt (optionally with self-excitation, see below). The gain 1/u₀
// may be annealed geometrically from u0_start to u0_end over `anneal_steps` steps (mean-field annealing). A
// step is O(n1n2n3).
//
//   sync   Jacobi: every h from the previous V; parallel over i-slices. The plane sums are
//          reduced through per-slice line sums in a fixed order, so results are bit-identical
//          for any thread count.
//   async  neurons in a random permutation per step, plane sums updated after each neuron.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_energy.hpp"

namespace trackassoc {

struct ContinuousParams {
  HopfieldWeights w;
  float dt = 0.05f;
  float tau = 1.f;  // 0 = no decay term
  float u0 = 0.02f;
  // λ ∈ [0, 1]: h += λ·(A+B+C+D)·(V − ½). λ = 1 makes h = −ΔE_on of the discrete network (primes
  // exclude the neuron), i.e. the gradient of the multilinear extension of the 0/1 energy, which
  // is linear in each V and so has its minima at vertices: the network then ends in 0/1 states
  // instead of split planes (two neurons at ½ satisfy (R−1)² = 0). λ = 0 is plain Hopfield–Tank.
  float self_excitation = 0.f;
};

struct ContinuousNetwork {
  const NormalisedCost* c = nullptr;
  std::vector<float> u, V;
  std::vector<double> R, S, T;  // plane sums of V
  double M = 0.0;

  explicit ContinuousNetwork(const NormalisedCost& cost);
  // u ← u_init + noise·N(0,1) per neuron, V and the marginals from u.
  void initialise(float u_init, float noise, float u0, CounterRng& rng);
  void recompute_marginals();
  // Energy of the current V (continuous form above, no integral term).
  double energy(const HopfieldWeights& w) const;
};

// One Euler step over all neurons; returns max |ΔV|.
float continuous_sync_step(ContinuousNetwork& net, const ContinuousParams& p);
// One Euler step neuron by neuron in `order`; returns max |ΔV|.
float continuous_async_step(ContinuousNetwork& net, const ContinuousParams& p,
                            std::span<const uint32_t> order);

}  // namespace trackassoc
