// The discrete 3-D Hopfield network and its sweep schedules (seed 000 Eq. 9–10 and §3.2;
// docs/design.md §4.4).
//
// Update rule (seed 000 Eq. 10 with 0/1 states): V ← 1 when net = −ΔE_on > 0, V ← 0 when
// net < 0, unchanged at net = 0. ΔE_on is the exact energy change of turning the neuron on,
// read from O(1) marginal sums (kernels/hopfield/hopfield_energy.hpp), so an asynchronous flip never
// raises the energy (the convergence argument of seed 000 Eq. 14).
//
// Schedules (one "sweep" visits every neuron once):
//   async     Gauss–Seidel in a given order (a fresh random permutation per sweep, or the fixed
//             cost order), marginals updated on every flip. Serial; O(n1n2n3) per sweep.
//             With temperature T > 0 the rule is Glauber's: V ← 1 with probability
//             1/(1+exp(ΔE_on/T)) (a Boltzmann machine; annealing T → 0 recovers Eq. 10).
//             At T = 0 the cost-ordered and random-order sweeps first settle each neuron from
//             the O(n) marginals alone: a neuron in occupied planes cannot turn on, and an active
//             neuron alone in its planes cannot turn off, whatever its state (and, in a random
//             order, whatever its cost within [c_lo, c_hi]). Only the undecided rest reads its
//             state (kept as one bit per neuron during the sweep) and its cost. The updates are
//             exactly those of the plain rule (tests/kernels/hopfield/test_hopfield_energy.cpp), and a sweep
//             near convergence streams its order instead of reading the state at random.
//   sync      Jacobi: every net input from the previous state, all neurons at once; parallel over
//             i-slices (TBB); new marginals are reduced with integer atomics, so the result is
//             independent of the thread count. A fraction < 1 updates only a pseudo-random subset
//             (damping). 2-cycles are detected with a Zobrist hash of the state.
//   diagonal  blocks of neurons that share no plane: kernels/hopfield/hopfield_diagonal.hpp.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_energy.hpp"

namespace trackassoc {

// Zobrist key of neuron a (for 2-cycle detection of the sync schedule).
inline uint64_t zobrist_key(std::size_t a) {
  return splitmix64_mix(a * 0x9e3779b97f4a7c15ULL + 0x5851f42d4c957f2dULL);
}

struct DiscreteNetwork {
  HopfieldEnergy form = HopfieldEnergy::kFullPlane;
  HopfieldWeights w;
  const NormalisedCost* c = nullptr;
  std::vector<uint8_t> V;
  HopfieldMarginals m;
  uint64_t hash = 0;  // Zobrist hash of V

  DiscreteNetwork(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c);
  // Sets the state and recomputes marginals and hash.
  void set_state(std::span<const uint8_t> state);
  double energy() const { return hopfield_energy(form, w, *c, V); }
  double delta_on(std::size_t a) const;
};

// One asynchronous sweep in `order` (indices into V). Returns the number of flips.
int64_t async_sweep(DiscreteNetwork& net, std::span<const uint32_t> order, double temperature = 0.0,
                    CounterRng* rng = nullptr);

// A fixed asynchronous order with what a sweep reads, laid out in that order: the neuron, its
// (i, j, k) and its ĉ. Built once per solve (the default "cost" order) and shared by every
// restart, so a sweep streams these arrays and reads only the state and the marginals at random.
// Needs n1, n2, n3 < 65536. O(K) memory (14 bytes per neuron).
struct OrderedSweepPlan {
  std::vector<uint32_t> neuron;
  std::vector<uint16_t> i, j, k;
  std::vector<float> cost;
  OrderedSweepPlan(std::span<const uint32_t> order, const NormalisedCost& c);
};
// async_sweep(net, plan.neuron) at temperature 0: the same updates in the same order, faster.
int64_t async_sweep_planned(DiscreteNetwork& net, const OrderedSweepPlan& plan);

// One asynchronous sweep slice by slice: the i-slices in `slice_order`; within slice i, neuron
// (j, k) = packed_jk[(p + rotation[i]) mod n2n3] for p = 0, 1, ... (packed as j << 16 | k). The
// same Gauss–Seidel rule as async_sweep, without index divisions and with the slice (n2·n3
// neurons) resident in cache. Needs n2, n3 < 65536.
int64_t async_sweep_slices(DiscreteNetwork& net, std::span<const uint32_t> slice_order,
                           std::span<const uint32_t> packed_jk, std::span<const uint32_t> rotation);

struct SyncSweepResult {
  int64_t flips = 0;
};
// One synchronous sweep. `fraction` in (0, 1]: the share of neurons updated (damping), chosen by a
// counter-based hash of (sweep_key, neuron), so it is deterministic for any thread count.
SyncSweepResult sync_sweep(DiscreteNetwork& net, double fraction = 1.0, uint64_t sweep_key = 0);

}  // namespace trackassoc
