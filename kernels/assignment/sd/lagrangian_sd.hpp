// Lagrangian relaxation for the S-D assignment with dummies (assignment_sd.hpp), S ≥ 3: the
// "relaxation algorithm" of seed 000 in S dimensions (Deb, Yeddanapudi, Pattipati, Bar-Shalom,
// IEEE TAES 33(2) 1997; Pattipati et al., IEEE TAC 37(2) 1992; MATLAB `assignsd`).
//
// The constraints of sensors 3 … S are relaxed with multipliers μ_s(i) (the dummy has μ = 0, since
// it is unconstrained). With c̃_t = c_t − Σ_{s≥3} μ_s(t_s):
//
//   L(μ) = LAP(d) + Σ_{t : t_1 = t_2 = dummy} min(0, c̃_t) + Σ_{s≥3} Σ_i μ_s(i),
//   d(i_1, i_2) = min over (i_3 … i_S) of c̃(i_1, i_2, i_3, …, i_S),
//
// where LAP(d) is the 2-D assignment of sensors 1 and 2 with dummies (every real index exactly once;
// match_dimension), and tuples whose first two indices are dummies are free in the relaxed problem.
// L(μ) is a lower bound on the optimum for every μ (the relaxed constraints are equalities, so μ is
// free in sign). μ is improved by subgradient ascent on g_s(i) = 1 − (uses of index i of sensor s
// in the relaxed solution), with the step rules of the 3-D solver (Polyak with θ halving, or
// diminishing, or Camerini–Fratta–Maffioli deflection; the driver of
// kernels/assignment/lagrangian_subgradient.hpp, shared with kernels/assignment/lagrangian_relaxation.hpp).
//
// Feasible recovery each iteration (Deb et al. §IV): keep the LAP's (i_1, i_2) pairs, then for
// s = 3 … S match the partial tuples to sensor s by match_dimension on the costs minimised over the
// sensors after s, with their multipliers; optionally polish by local search (lr+ls). It reports the
// best lower bound, the best upper bound and the relative and absolute gap, and stops at a gap
// tolerance, an iteration limit or a time limit.
//
// Cost per iteration: one pass over the dense tensor, Π(n_s+1), parallel over i_1 (bit-identical for
// any thread count), plus S−1 LAPs of size ≤ 2n. For S = 3 it solves the same problem as
// kernels/assignment/lagrangian_relaxation.hpp, but with dummies in every sensor instead of the canonical
// form.
#pragma once

#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc {

// Options as for the 3-D relaxation (LagrangianOptions; lr+ls = local_search, with
// local_search_options.max_rounds passes of polish_sd). S = 2 is solved exactly by one LAP (termination
// optimal); S ≥ 3 by the relaxation above.
SolutionSD solve_lagrangian_sd(const CostTensorSD& c, const LagrangianOptions& options = {});

}  // namespace trackassoc
