// Lagrangian relaxation for the 3-D assignment: the "relaxation algorithm" seed 000 compares its
// Hopfield network against (Pattipati, Deb, Bar-Shalom, Washburn, "A new relaxation algorithm and
// passive sensor data association", IEEE TAC 37(2) 1992; Deb et al., IEEE TAES 33(2) 1997; MATLAB
// `assignsd`; the NRL Tracker Component Library `assign3D`).
//
// On the canonical problem (assignment_canonical.hpp: n1 ≤ n2 ≤ n3, complete tuples) the
// constraints of dimension k are relaxed with multipliers μ_k:
//
//   L(μ) = min_x Σ_ijk (b_ijk + μ_k) x_ijk − Σ_k μ_k      s.t. each i once, each j at most once
//        = LAP(c) − Σ_k μ_k,   c_ij = min_k (b_ijk + μ_k)                   (Pattipati Eq. 14–16)
//
// a 2-D LAP solved by Jonker–Volgenant. For any μ (μ ≥ 0 when n3 > n1, since the relaxed
// constraints are then "≤ 1") L(μ) is a lower bound on the optimum. μ is improved by projected
// subgradient ascent on g_k = (Σ_ij x_ijk) − 1 (the driver of kernels/assignment/lagrangian_subgradient.hpp,
// shared with the S-D relaxation):
//   - Polyak:      μ ← μ + θ (UB − L(μ)) g / ‖g‖²,   θ halved after `theta_patience` iterations
//                  without a better bound (Held, Wolfe, Crowder 1974);
//   - diminishing: μ ← μ + θ Δ₀ g / (‖g‖² √(t+1)),  Δ₀ = UB − L at the first iteration;
//   - deflected:   Camerini–Fratta–Maffioli (1975): direction d = g + β d_prev with
//                  β = max(0, −1.5 gᵀd_prev / ‖d_prev‖²), Polyak length along d.
// Each iteration recovers a feasible solution: the LAP pairs (i, j) are matched to k by a second
// LAP on b_ijk (Pattipati §III-C), optionally polished by local search (lr+ls). It reports the best
// lower bound (rounded up when every cost is an integer), the best upper bound and the relative and
// absolute gap, and stops at the gap tolerance, an iteration limit or a time limit.
//
// Cost per iteration: O(n1·n2·n3) for c (parallel over i with parallel_for_range; bit-identical for
// any thread count) plus two LAPs, O(n³) worst case.
//
// Unequal sizes: handled by the canonical form (the largest dimension is the relaxed one). The
// dummy index (finite miss_cost) by padding, see assignment_canonical.hpp.
//
// S > 3 dimensions, and dummies in every dimension: kernels/assignment/sd/lagrangian_sd.hpp (this
// header is the axial 3-D form on a CostTensor3).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class StepRule { kPolyak, kDiminishing, kDeflected };
inline constexpr EnumName<StepRule> kStepRuleNames[]{{StepRule::kPolyak, "polyak"},
                                                     {StepRule::kDiminishing, "diminishing"},
                                                     {StepRule::kDeflected, "deflected"}};
constexpr std::span<const EnumName<StepRule>> enum_names(StepRule) { return kStepRuleNames; }

struct LagrangianOptions {
  int max_iterations = 300;
  double relative_gap_tolerance = 1e-3;  // stop when (UB − LB) / max(|UB|, 1e-9) ≤ this
  double absolute_gap_tolerance = 1e-9;  // or when UB − LB ≤ this (then termination = optimal)
  double time_limit_s = std::numeric_limits<double>::infinity();
  StepRule step_rule = StepRule::kPolyak;
  double theta = 2.0;         // initial step scale θ ∈ (0, 2]
  int theta_patience = 8;     // halve θ after this many iterations without a better bound
  double min_theta = 1e-6;    // stop (iteration limit) when θ falls below this
  bool local_search = false;  // polish each recovered solution (the lr+ls solver)
  LocalSearchOptions local_search_options;
  void validate() const;
};

// Canonical-level state, reused by branch and bound.
struct LagrangianRun {
  std::vector<Tuple3> best_tuples;  // canonical, complete (empty if none found)
  double upper_bound = std::numeric_limits<double>::infinity();
  double lower_bound = -std::numeric_limits<double>::infinity();
  std::vector<double> best_multipliers;  // μ at the best bound (size n3)
  int64_t iterations = 0;
  Termination termination = Termination::kIterationLimit;
};

// Runs the relaxation on a canonical problem starting from `initial_multipliers` (empty: zeros).
LagrangianRun run_lagrangian(const CanonicalProblem3& p, const LagrangianOptions& options,
                             const std::vector<double>& initial_multipliers = {});

// Building blocks shared with the clique relax-and-cut (clique_cuts.hpp) and branch and bound.
// c_ij = min_k (w_ijk + μ_k) and its argmin (the first k attaining it; Pattipati Eq. 16) for a
// row-major n1×n2×n3 cost array w: the float tensor, or penalised costs in double. Parallel over i
// (each (i, j) computed by one task alone: bit-identical for any thread count). O(n1·n2·n3).
void reduce_over_k(const float* w, int32_t n1, int32_t n2, int32_t n3, const std::vector<double>& mu,
                   std::vector<double>& c, std::vector<int32_t>& arg);
void reduce_over_k(const double* w, int32_t n1, int32_t n2, int32_t n3, const std::vector<double>& mu,
                   std::vector<double>& c, std::vector<int32_t>& arg);
// Matches the pairs (i, row_to_col[i]) to k by a LAP on b_{i j_i k} (Pattipati §III-C): complete
// canonical tuples, or empty if none of finite cost exists. `matrix` is scratch.
std::vector<Tuple3> recover_feasible(const CostTensor3& b, const std::vector<int32_t>& row_to_col,
                                     std::vector<double>& matrix);
// Σ b over the tuples.
double tuples_cost(const CostTensor3& b, const std::vector<Tuple3>& t);

// The solver: canonicalise, relax, map back. lower_bound, gap and abs_gap are filled.
Solution3 solve_lagrangian3(const CostTensor3& cost, const LagrangianOptions& options = {});

}  // namespace trackassoc
