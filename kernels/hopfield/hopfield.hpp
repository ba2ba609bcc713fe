// Hopfield solvers for the 3-D assignment with restarts (seed 000 §3, seed 004; docs/design.md §4.4).
//
// One restart: normalise the cost (ĉ ∈ [0, 1]), set the initial state, run sweeps of the chosen
// schedule (kernels/hopfield/hopfield_discrete.hpp, kernels/hopfield/hopfield_continuous.hpp) until no neuron
// changes (discrete), max |ΔV| < tolerance (continuous), a 2-cycle (sync), or max_sweeps; then
// decode and repair (kernels/hopfield/hopfield_decode.hpp). R restarts run in parallel over TBB, each
// with its own stream CounterRng(seed, 0, restart), so results are bit-identical for any thread
// count. The best repaired objective wins (ties: the lowest restart).
//
// Why the defaults (measured with `trackassoc experiment schedules`; the numbers are in README
// "Status"): with E·ĉ_max below (A+B+C+D)/2 every valid assignment is a fixed point of the
// full-plane network, so the discrete dynamics cannot improve a valid state, and from an empty
// start they stop at whatever assignment they first complete (260–430 % above the LR bound on the
// seed 000 tracking instances, worse than greedy). The quality must come from the start. The
// default start is mean-field annealing: the continuous network of the same energy (CHNN) with its
// gain annealed from u0_start to u0_end over gain_anneal_steps, with a small self-excitation
// (λ = 0.1) that drives it to 0/1 states; its V > ½ state seeds the discrete network, which then
// resolves the remaining conflicts and fills the free planes by exact energy descent in ascending
// cost order (every free triple switches on since E < (A+B+C)/2 on ĉ ≤ 1). Measured: 0 % gap to
// the LR bound on 40 of 40 seed 000 tracking instances (n = 10–100; the greedy start 2.3–3.3 %
// mean at n = 50–100, greedy alone 2–7 %), and 0–4.3 % above the optimum on DecompLib
// n = 20–40, 0–3.1 % with polish (greedy+ls 6–10 %, LR 1.4–2.8 %). Also available: E annealing
// (anneal_E_factor > 1: expensive tuples dissolve and their indices recombine) and Glauber
// temperature; both measured worse than the mean-field start.
// After the gain annealing the sync Euler step at u0_end (dt = 0.05, beyond the async Lyapunov
// bound 4u₀/(A+B+C+D) = 0.027) keeps some neurons oscillating, so max |ΔV| rarely falls below
// the tolerance and the mean-field phase usually runs its mean_field_steps: the decoded state
// V > ½ has settled by then on the tracking instances, and stays chaotic on random costs.
// (Tried and not kept: capping dt at f·4u₀/(A+B+C+D), f = 0.5–2, still ran 300 steps at n = 100
// and changed no gap materially; stopping once no neuron crossed ½ for 20 steps shortened few
// restarts and counting the crossings slowed every Euler step by 15 %.)
// What the restarts buy: the annealing starts at a high temperature, which forgets the initial
// noise, so on the tracking instances all 8 restarts end at the same assignment (1 distinct
// objective of 8 on seed 000 n = 20 and 50): `restarts = 1` gives the same answer for 1/8 of the
// CPU there. On random-cost instances the post-annealing Euler steps stay chaotic and the restarts
// differ (DecompLib n = 30–40: 2–7 distinct objectives of 8), so the default keeps 8. Running the
// mean-field phase of restarts ≥ 1 on ĉ + σ·U(0, 1) to diversify them was measured worse on
// DecompLib n = 30–40 for every σ in 0.05–0.4.
// Complexity: O(R · sweeps · n1n2n3); memory O(n1n2n3) per concurrent restart.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/enum_names.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_decode.hpp"
#include "kernels/hopfield/hopfield_energy.hpp"

namespace trackassoc {

// Which network runs: the discrete network (seed 000 Eq. 9–10) or the continuous one (CHNN,
// seed 004; kernels/hopfield/hopfield_continuous.hpp), whose Euler steps are sync or async by
// HopfieldOptions::continuous_async.
enum class HopfieldNetwork { kDiscrete, kContinuous };
// Update order of the discrete network's sweeps (kernels/hopfield/hopfield_discrete.hpp,
// kernels/hopfield/hopfield_diagonal.hpp): all neurons at once, one at a time, or by diagonal blocks.
enum class HopfieldSchedule { kSync, kAsync, kDiagonal };
// Initial state of the discrete network: all off; random with density init_density·N/K; the
// cost-ordered greedy assignment; or the mean-field state (the continuous network of this restart
// annealed with the continuous options, thresholded at V > ½).
enum class HopfieldInit { kZero, kRandom, kGreedy, kMeanField };
// Async visiting order: kRandom = a uniform random permutation of all neurons per sweep;
// kSliceRandom = the i-slices in random order, within each slice a random permutation of the
// (j, k) pairs entered at a random rotation (cache friendly: a slice is n2·n3 neurons; see
// SliceRandomOrder); kCost = ascending normalised cost, fixed. With a Glauber temperature,
// kSliceRandom falls back to kRandom.
enum class HopfieldOrder { kRandom, kSliceRandom, kCost };

inline constexpr EnumName<HopfieldNetwork> kHopfieldNetworkNames[]{
    {HopfieldNetwork::kDiscrete, "discrete"}, {HopfieldNetwork::kContinuous, "continuous"}};
constexpr std::span<const EnumName<HopfieldNetwork>> enum_names(HopfieldNetwork) {
  return kHopfieldNetworkNames;
}
inline constexpr EnumName<HopfieldSchedule> kHopfieldScheduleNames[]{
    {HopfieldSchedule::kSync, "sync"},
    {HopfieldSchedule::kAsync, "async"},
    {HopfieldSchedule::kDiagonal, "diagonal"}};
constexpr std::span<const EnumName<HopfieldSchedule>> enum_names(HopfieldSchedule) {
  return kHopfieldScheduleNames;
}
inline constexpr EnumName<HopfieldInit> kHopfieldInitNames[]{{HopfieldInit::kZero, "zero"},
                                                             {HopfieldInit::kRandom, "random"},
                                                             {HopfieldInit::kGreedy, "greedy"},
                                                             {HopfieldInit::kMeanField, "mean_field"}};
constexpr std::span<const EnumName<HopfieldInit>> enum_names(HopfieldInit) { return kHopfieldInitNames; }
inline constexpr EnumName<HopfieldOrder> kHopfieldOrderNames[]{{HopfieldOrder::kRandom, "random"},
                                                               {HopfieldOrder::kSliceRandom, "slice_random"},
                                                               {HopfieldOrder::kCost, "cost"}};
constexpr std::span<const EnumName<HopfieldOrder>> enum_names(HopfieldOrder) { return kHopfieldOrderNames; }
// The kSliceRandom order of one sweep (for async_sweep_slices): the slices in random order, one
// random permutation of the (j, k) pairs per sweep, entered at a random rotation in every slice.
// n2 + n1 + n2·n3 random draws per sweep instead of n1·n2·n3.
struct SliceRandomOrder {
  std::vector<uint32_t> slices, packed_jk, rotation;
  void draw(int32_t n1, int32_t n2, int32_t n3, CounterRng& rng);
};

struct HopfieldOptions {
  HopfieldEnergy energy = HopfieldEnergy::kFullPlane;
  HopfieldNetwork network = HopfieldNetwork::kDiscrete;
  HopfieldSchedule schedule = HopfieldSchedule::kAsync;  // the discrete network's sweeps
  // true: A = B = C = 1, D = 0 (printed energy: D = 1) and E just below the fixed-point bound
  // (fixed_point_E_bound) on the normalised cost; false: `weights` as given (N is always set to
  // min(n1, n2, n3)).
  bool auto_weights = true;
  HopfieldWeights weights;
  int32_t restarts = 8;
  int32_t max_sweeps = 300;  // discrete sweeps, or continuous Euler steps
  HopfieldInit init = HopfieldInit::kMeanField;
  double init_density = 1.0;  // random init: each neuron on with probability density·N/(n1n2n3)
  double greedy_noise = 0.2;  // restarts ≥ 1: cost order of ĉ + noise·U(0,1)
  HopfieldOrder order = HopfieldOrder::kCost;  // async order within a sweep
  // E annealing (discrete): E_s = E_final·factor^(1 − s/anneal_sweeps) for s < anneal_sweeps.
  double anneal_E_factor = 1.0;
  int32_t anneal_sweeps = 20;
  // Glauber temperature (async only): T_s = T0·(1 − s/anneal_sweeps) for s < anneal_sweeps, then 0.
  double temperature = 0.0;
  double damping = 1.0;  // sync: share of neurons updated per sweep, (0, 1]
  // continuous (CHNN, and the mean-field start of the discrete network)
  bool continuous_async = false;  // async Euler steps (neuron by neuron) instead of sync (Jacobi)
  double dt = 0.05, tau = 0.0;
  double u0_start = 0.5, u0_end = 0.02;  // gain 1/u₀ annealed geometrically over gain_anneal_steps
  // 250 of the 300 steps anneal the gain (100 until session 4): at the same step budget and time
  // the slower annealing lands closer to the optimum. Mean gap of the default hopfield, on two
  // separate instance sets: geometric n = 50, 6.6 → 3.1 % and 5.3 → 3.4 % (n = 30: 1.4 → 0.7 %);
  // DecompLib n = 20–40, 3.3 → 2.0 % over 30 instances; seed 000 tracking unchanged at 0 %. chnn
  // likewise (geometric n = 50: 5.9 → 2.4 % and 4.2 → 3.2 %).
  int32_t gain_anneal_steps = 250;
  double noise = 0.01;           // initial u noise, in units of u0_start
  double self_excitation = 0.1;  // λ of ContinuousParams (1 = multilinear energy)
  double tolerance = 1e-4;       // continuous: stop when max |ΔV| < tolerance
  // init mean_field: Euler steps (max) of the continuous phase: gain_anneal_steps, then 50 at the
  // final gain. (With the earlier 100 annealing steps, 200 steps in all instead of 300 gave the
  // same 0 % gap on 34 seed 000 tracking instances for 25 % less time, but on geometric instances,
  // n = 50, 8 each, 8.5 → 11.0 %, 3.6 → 4.2 % and 5.5 → 9.2 % above the LR bound at noise 0.1,
  // 0.3 and 0.5; spending the 300 on a slower annealing was better still, see gain_anneal_steps.)
  int32_t mean_field_steps = 300;
  HopfieldRepair repair = HopfieldRepair::kGreedy;
  // Polish every restart's repaired assignment by the dimension-wise LAP local search
  // (kernels/assignment/local_search.hpp, docs/design.md §4.5) before choosing the best.
  bool polish = false;
  bool trace = false;  // record the energy after every sweep, per restart
  void validate() const;
};

struct HopfieldRestart {
  double energy = 0.0;              // final network energy (final weights)
  double objective = 0.0;           // cost of the repaired (and, with polish, polished) assignment
  double repaired_objective = 0.0;  // before polish
  bool raw_feasible = false;
  int64_t sweeps = 0;
  int64_t mean_field_steps = 0;  // init mean_field: continuous steps before the discrete sweeps
  Termination termination = Termination::kIterationLimit;
  std::vector<float> energy_trace;  // per sweep, when options.trace
};

struct HopfieldResult {
  Solution3 solution;  // the best restart, repaired; summary.sweeps = its sweeps
  std::vector<HopfieldRestart> restarts;
  double raw_validity_rate = 0.0;  // share of restarts whose network state was a valid assignment
  int32_t best_restart = -1;
  HopfieldWeights weights;  // the final weights used (normalised-cost units)
};

// "continuous" for the continuous network, else the discrete schedule's name (the summary message).
const char* hopfield_schedule_label(const HopfieldOptions& options);

// Indices 0..K−1 in ascending order of c, ties in ascending index (the order of std::stable_sort
// by c), by an LSD radix sort of the float keys: O(K), serial. The async "cost" order; c must not
// hold NaN.
std::vector<uint32_t> ascending_cost_order(std::span<const float> c);

// The weights the solver uses for a normalised cost (auto or as given, N filled in).
HopfieldWeights hopfield_weights(const HopfieldOptions& options, const NormalisedCost& c);

HopfieldResult solve_hopfield(const CostTensor3& cost, const HopfieldOptions& options, uint64_t seed);

// The per-restart table of a result (restart, raw validity, sweeps, mean-field steps, energy,
// repaired and final objective), as /associations/<name>/restarts/ stores it.
RestartTable hopfield_restart_table(const HopfieldResult& result);

}  // namespace trackassoc
