// The projected subgradient ascent on a Lagrangian dual, shared by the 3-D relaxation
// (kernels/assignment/lagrangian_relaxation.hpp) and the S-D relaxation
// (kernels/assignment/sd/lagrangian_sd.hpp) (Held, Wolfe, Crowder, "Validation of subgradient optimization",
// Math. Prog. 6, 1974; Camerini, Fratta, Maffioli, Math. Prog. Study 3, 1975; Pattipati et al., IEEE TAC
// 37(2) 1992).
//
// The problem supplies two callbacks: the dual subproblem, which at multipliers μ returns
// L(μ) (a lower bound on the optimum) and a subgradient g of L at μ (already projected when μ is
// sign-constrained), and the primal recovery, which turns the last relaxed solution into a
// feasible one and keeps it when it beats the incumbent. Each iteration:
//
//   1. L(μ), g ← dual(μ); an infeasible subproblem ends the run (termination infeasible, LB = +∞).
//   2. LB ← max(LB, L(μ)); after `theta_patience` iterations without a better bound θ ← θ/2.
//   3. UB ← primal(UB).
//   4. Stop at the gap test (below), with an incumbent; at g = 0 (the relaxed solution satisfies
//      the relaxed constraints; see zero_subgradient_is_optimal); at the time limit; or at θ <
//      min_theta.
//   5. Step with Δ = max(T − L(μ), 10⁻¹² max(1, |L(μ)|)), target T = UB (5 % above L(μ) while
//      there is no incumbent):
//        Polyak       μ ← μ + θ Δ g / ‖g‖²
//        diminishing  μ ← μ + θ₀ Δ₀ g / (‖g‖² √(t+1)),   Δ₀ = Δ at the first step
//        deflected    d ← g + β d,  β = max(0, −1.5 gᵀd / ‖d‖²) (0 at t = 0),  μ ← μ + θ Δ d / ‖d‖²
//      then μ ← max(μ, 0) for the sign-constrained multipliers (all, or those past free_sign_count).
//
// Gap test, in this order: UB − LB ≤ absolute_gap_tolerance → optimal; with integer costs
// UB − LB < 1 − 10⁻⁷ → optimal; (UB − LB) / max(|UB|, 10⁻⁹) ≤ relative_gap_tolerance → gap
// tolerance. At the iteration limit the termination is "iteration limit" with an incumbent and
// "infeasible" without one.
//
// Every sum runs over μ in index order, so a problem that lays its multipliers out in the order of
// its former hand-written loop gets bit-identical iterates. Cost per iteration: the callbacks plus
// O(|μ|).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"

namespace trackassoc {

struct SubgradientProblem {
  // L(μ) into `bound` and a subgradient into `g` (sized like μ); false when the subproblem has no
  // finite solution (the primal problem is then infeasible).
  std::function<bool(const std::vector<double>& mu, double& bound, std::vector<double>& g)> dual;
  // A feasible solution recovered from the last dual solution at μ: when it costs less than
  // `incumbent` the problem keeps it and returns its cost, else returns `incumbent`.
  std::function<double(const std::vector<double>& mu, double incumbent)> primal;
  bool integer_costs = false;  // the gap test's "UB − LB < 1" (bounds rounded up by the dual)
  bool nonnegative = false;    // μ ≥ 0 (relaxed "≤ 1" constraints): project after every step
  // With `nonnegative`: the first free_sign_count multipliers stay free in sign (relaxed equalities
  // beside relaxed "≤" cuts, as in the clique relax-and-cut of kernels/assignment/clique_cuts.hpp).
  std::size_t free_sign_count = 0;
  // g = 0 without a closed gap: true ends the run as optimal (relaxed equalities: the relaxed
  // solution is feasible, hence optimal); false ends it at the time limit if that has passed,
  // else as at the iteration limit (the 3-D relaxation, whose bound is rounded).
  bool zero_subgradient_is_optimal = false;
};

// One iteration, for a trace.
struct SubgradientIterate {
  double bound = 0.0;        // L(μ) of this iteration
  double lower_bound = 0.0;  // best L so far
  double upper_bound = 0.0;  // incumbent cost after the recovery (+∞: none)
  double theta = 0.0;        // θ after this iteration's halving
  double step = 0.0;         // step length taken (0 when the run stopped here)
};

struct SubgradientResult {
  double lower_bound = -std::numeric_limits<double>::infinity();
  double upper_bound = std::numeric_limits<double>::infinity();
  std::vector<double> multipliers;       // μ at the end
  std::vector<double> best_multipliers;  // μ at the best bound
  int64_t iterations = 0;
  Termination termination = Termination::kIterationLimit;
};

// Runs the ascent from `mu` (its size fixes |μ|) with options' max_iterations, gap tolerances,
// time_limit_s (measured from `start`), step_rule, theta, theta_patience and min_theta (validated
// by the caller). `trace`, when given, receives one row per iteration.
SubgradientResult run_subgradient(const SubgradientProblem& problem, std::vector<double> mu,
                                  const LagrangianOptions& options,
                                  std::chrono::steady_clock::time_point start,
                                  std::vector<SubgradientIterate>* trace = nullptr);

}  // namespace trackassoc
