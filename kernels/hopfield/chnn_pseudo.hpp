// The improved CHNN of seed 004 (Bai, Gao 2014, §2): a continuous Hopfield network over S sensors
// with unequal track counts, made square by pseudo-tracks.
//
// Extended index sets (seed 004 §2(2)). Sensor 1 (the reference, "A") keeps its n_1 tracks. Every
// later sensor s gets, before its own n_s tracks, pseudo-tracks: copies of the tracks of sensors
// 1 … s−1, so its extended size is n_1 + … + n_s (the paper's j ∈ 1…N, l ∈ 1…N+M, m ∈ 1…N+M+S).
// A neuron is an extended tuple (x_1, …, x_S); choosing a copy at sensor s means "the target has no
// track at sensor s".
//
// Cost (Eq. 9 generalised to S sensors, the chain form b = D_12 + D_23 + …): each link between
// consecutive sensors s, s+1 costs, with u the track x_s stands for and v the one x_{s+1} stands for,
//   v a real track of sensor s+1:    D = d(u, v), the association distance       (Eq. 7)
//                                    and +∞ when d(u, v) is outside the gate    (Eq. 12, gated)
//   v the copy of u itself:          D = λ, slightly above the statistical gate (Eq. 7)
//   v a copy of any other track:     D = +∞ (two tracks of one sensor are never one target).
// Seed 004's Eqs. 7 and 12 were lost from the text; this is the reading of its description ("λ_j
// is slightly larger than the statistical gate"; after Eq. 12 "a large number of b tend to infinity,
// so the neurons of impossible pairs are in the right state, which speeds up convergence"). The
// "other copy = +∞" rule is ours: without it a track could join another track of its own sensor.
// Neurons of infinite cost are fixed at V = 0 and never stored, so the network is a sparse list of
// finite tuples; Eq. 12's gating shrinks that list.
//
// Network (Hopfield–Tank; the paper's Eqs. 5, 6, 8, 10, 11 were lost, docs/design.md §4.4): with R_s(x)
// the sum of V over the neurons whose sensor-s index is x and M = Σ V,
//   E = A/2 Σ_{s≥2} Σ_x R_s(x)(R_s(x) − 1)   each extended column at most once     (term 1)
//     + B/2 Σ_j (R_1(j) − 1)²                 each reference track exactly once    (term 2)
//     + C Σ ĉ_t V_t                           the association cost, ĉ = min(b/b_ref, 2) (term 3)
//     + D/2 (M − n_1)²                        the global term that speeds convergence (term 4)
//   h_t = −∂E/∂V_t = −A Σ_{s≥2} (R_s(t_s) − V_t) − B (R_1(t_1) − 1) − C ĉ_t − D (M − n_1),
//   du/dt = −u/τ + h,  V = ½(1 + tanh(u/u₀)),  explicit Euler steps of size dt (Jacobi: every h
//   from the previous V; parallel over neurons, bit-identical for any thread count).
// It stops when max |Δu|/u₀ < tolerance (converged) or at max_steps. Decoding: neurons by V
// descending, each accepted when its reference track and extended indices are still free; a
// reference track left over takes its all-copies tuple (always finite and free). Tracks of sensors
// 2 … S in no accepted tuple stay alone. Limitation of the paper's formulation: two tracks that the
// reference sensor did not see cannot be grouped. Our extension (leftover_passes): the tracks left
// alone on sensors 2 … S form a smaller problem of the same kind, with the sensor holding most of
// them as the reference, solved again, up to S − 2 times (0 = the paper's single pass).
//
// b_ref is the costliest all-pseudo chain, Σ_s max λ. Cost per step O(K·S) for K stored neurons.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc {

struct PseudoTrackInput {
  std::vector<int32_t> n;  // real tracks per sensor, sensor 0 = the reference
  // distance[pair(a, b)] for a < b: n_a × n_b row-major, d ≥ 0 or +inf (not a candidate).
  std::vector<std::vector<double>> distance;
  std::vector<double> pseudo_cost;  // λ per pair (a, b), a < b: a track of a with no track at b
  static std::size_t pair(int32_t a, int32_t b, int32_t S) {  // a < b
    return static_cast<std::size_t>(a) * S + b;
  }
  void validate() const;
};

struct ChnnPseudoOptions {
  double A = 1.0, B = 1.0, C = 1.0, D = 0.0;  // energy weights (terms 1–4)
  double dt = 0.02;                           // Euler step
  double tau = 1.0;                           // decay time constant; 0 = no decay
  double u0 = 0.05;                           // gain 1/u₀ of V = ½(1 + tanh(u/u₀))
  int max_steps = 2000;
  double tolerance = 1e-3;  // converged when max |Δu|/u₀ of a step falls below this
  double noise = 0.01;      // initial u = u0·atanh(2V₀ − 1) + noise·N(0,1), V₀ = 1/(row size)
  uint64_t seed = 1;
  int leftover_passes = -1;  // extra passes over the tracks left alone; −1 = S − 2, 0 = the paper's
  void validate() const;
};

struct ChnnPseudoResult {
  SolutionSD solution;  // tuples over the real tracks (kNoTrack = missing); objective unset
  int64_t neurons = 0;  // stored (finite-cost) neurons, summed over passes
  int64_t steps = 0;    // Euler steps, summed over passes
  int32_t passes = 0;
  bool converged = false;  // every pass converged
  double wall_time_s = 0.0;
};

// The finite neurons (exposed for tests): extended tuples K×S with their cost b (Eq. 9 chain),
// and for every sensor s the (sensor, track) each extended index stands for.
struct PseudoNeurons {
  int32_t S = 0;
  std::vector<int32_t> idx;
  std::vector<double> cost;
  std::vector<std::vector<std::pair<int32_t, int32_t>>> stands_for;  // [s][x] = (sensor, track)
  std::size_t size() const { return cost.size(); }
};
PseudoNeurons enumerate_pseudo_neurons(const PseudoTrackInput& input);

ChnnPseudoResult solve_chnn_pseudo(const PseudoTrackInput& input, const ChnnPseudoOptions& options = {});

}  // namespace trackassoc
