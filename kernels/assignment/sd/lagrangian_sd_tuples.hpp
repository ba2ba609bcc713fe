// Lagrangian relaxation of the S-D assignment with dummies over an enumerated list of candidate
// tuples (the sparse S-D form): memory linear in the candidate tuples, with a lower bound and so a
// duality gap for every solve (docs/design.md §4.10, "giant components, certified").
//
// Problem (kernels/assignment/sd/assignment_sd.hpp), restricted to the listed tuples: choose tuples
// of the list so that every real index of every sensor is in exactly one,
//   min Σ_t c_t x_t  s.t.  Σ_{t : t_s = i} x_t = 1  for every sensor s and real index i.
// The list must hold every real index's singleton (the tuple of that index alone), so the problem
// is always feasible. The dense tensor of Π(n_s + 1) entries is never formed: a giant component of
// 3 × 30 000 tracks has ~10¹³ entries but ~10⁵ allowed tuples.
//
// Relaxation (Deb, Yeddanapudi, Pattipati, Bar-Shalom, "A generalized S-D assignment algorithm for
// multisensor-multitarget state estimation", IEEE TAES 33(2) 1997, §III; Poore & Rijavec, SIAM J.
// Optim. 3(3) 1993): the two sensors with most tracks, a and b, are kept; the constraints of the
// others are relaxed with multipliers μ_s(i) (free in sign: equalities). With c̃_t = c_t − Σ_{s ∉
// {a,b}} μ_s(t_s),
//   L(μ) = Σ_i r(i) + Σ_j q(j) + LAP₀(d − r − q) + Σ_{t: t_a = t_b = dummy} min(0, c̃_t) + Σ μ,
// where d(i, j) = min c̃ over the tuples with (t_a, t_b) = (i, j), r(i) = the same with t_b the dummy,
// q(j) with t_a the dummy (finite: the singletons), and LAP₀ is the sparse 2-D assignment of a's
// tracks to b's (kernels/assignment/lap_sparse.hpp) in which a track may stay unmatched at cost 0
// (it then takes its r or q). L(μ) ≤ optimum for every μ. μ is improved by the subgradient ascent
// of kernels/assignment/lagrangian_subgradient.hpp on g_s(i) = 1 − uses of index i in the relaxed
// solution.
//
// Feasible recovery each iteration (the "Lagrangian heuristic"): the relaxed solution's tuples,
// then every listed tuple, in ascending c̃ order; a tuple is taken when none of its indices is taken
// yet and it costs less than its members' singletons; indices left over take their singletons.
// The best recovered solution is the upper bound; (UB − LB) / |UB| is the reported gap.
//
// Complexity, per iteration: O(T·S) for the reduced costs and the minima over T tuples, a sparse
// LAP over the E ≤ T (a, b) keys, and O(T log T) for the recovery's sort. Memory O(T·S + n).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc {

struct TupleListSD {
  std::vector<int32_t> n;       // real tracks per sensor; S = n.size() ≥ 2
  std::vector<int32_t> tuples;  // size() × S, kNoTrack for the dummy; at least one real index each
  std::vector<double> cost;     // one finite cost per tuple
  int32_t dims() const { return static_cast<int32_t>(n.size()); }
  std::size_t size() const { return cost.size(); }
  // InputError naming the field: sizes, index ranges, a NaN or infinite cost, an all-dummy tuple,
  // or a real index without its singleton.
  void validate() const;
  std::size_t bytes() const { return tuples.size() * sizeof(int32_t) + cost.size() * sizeof(double); }
};

// The solution's tuples (rows of the list, copied out) with objective, lower bound and gap. Uses
// options' max_iterations, gap tolerances, time limit and step rule (local_search is ignored).
SolutionSD solve_lagrangian_sd_tuples(const TupleListSD& problem, const LagrangianOptions& options = {});

}  // namespace trackassoc
