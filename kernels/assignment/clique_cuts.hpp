// Relax-and-cut with the clique facets of the 3-D axial assignment polytope: the root bound of the
// exact solver (branch_and_bound.hpp).
//
// Clique inequalities (Balas & Saltzman, "Facets of the three-index assignment polytope", Discrete
// Appl. Math. 23, 1989; separated in linear time by Balas & Qi, Math. Prog. 62, 1993): two tuples
// conflict when they share an index. For a tuple r = (i, j, k) the set
//     Q(r) = {r} ∪ {s : s shares exactly two indices with r}     (3n − 2 tuples for a cube)
// is a clique of that conflict graph (any two members share an index with each other), so every
// assignment satisfies  Σ_{s ∈ Q(r)} x_s ≤ 1; for n ≥ 3 it defines a facet. These cuts lift the LP
// bound to the optimum on the DecompLib ap3 instances tried (ap3.30.1, ap3.40.1, ap3.50.1: LP 174.2,
// 228.5, 276.0 → 177, 231, 279 after one round of 16–29 cuts, by CLP).
//
// Relax-and-cut (Lucena 2005, "Non delayed relax-and-cut algorithms", Ann. Oper. Res. 140): the
// cuts of a pool are relaxed beside the k constraints, with multipliers λ_c ≥ 0:
//     L(μ, λ) = LAP_{I×J}( min_k w_ijk + μ_k ) − Σ_k μ_k − Σ_c λ_c,
//     w_s = b_s + Σ_{c : s ∈ Q(r_c)} λ_c                          (the penalised costs)
// still one 2-D LAP per evaluation, and a lower bound for every μ (sign-constrained as in
// lagrangian_relaxation.hpp) and λ ≥ 0, since each relaxed cut has slack ≥ 0. The subgradient of
// cut c is (Σ_{s ∈ Q(r_c)} x_s) − 1 at the relaxed solution x, O(1) per cut from x's row of i and
// of j. Rounds alternate a projected subgradient ascent on a fixed pool (lagrangian_subgradient.hpp,
// warm-started from the best multipliers so far) with separation: the relaxed solution is
// integral with each i and j once, so the cuts it violates are exactly those two tuples sharing a
// k point at, Q((i1, j2, k)) and Q((i2, j1, k)) for x_{i1 j1 k} = x_{i2 j2 k} = 1 (a clique can
// hold two members of x only through a shared k). Candidates seen during a round are added, the
// most frequent first, up to `cuts_per_round`. The rounds stop when the gap closes, after
// `stall_rounds` rounds without a better bound, or (integer costs) when the pace of the bound since
// the first round cannot reach the next integer in the rounds left (Balas–Saltzman: the cuts
// barely move the bound there).
//
// Each evaluation recovers a feasible solution from the LAP pairs (lagrangian_relaxation.hpp's
// recovery) polished by local search, on the true costs b. Cost per evaluation: O(n1·n2·n3) for
// the reduction and the penalty updates of the changed cuts (3n per cut), plus two LAPs and the
// polish. The penalised tensor w is returned rebuilt from scratch from the best λ, so the bound of
// branch and bound over w matches its multipliers exactly.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"

namespace trackassoc {

struct CliqueCutOptions {
  int max_rounds = 40;            // separation rounds; 0 turns the cuts off
  int iterations_per_round = 40;  // subgradient iterations on each fixed pool
  int cuts_per_round = 100;       // new cuts added per round at most
  int stall_rounds = 4;           // stop after this many rounds without a better bound
  double theta = 1.0;             // initial Polyak step scale of each round, in (0, 2]
  void validate() const;
};

struct CliqueRelaxation {
  std::vector<Tuple3> roots;                                      // cut c is Σ_{s ∈ Q(roots[c])} x_s ≤ 1
  std::vector<double> lambda;                                     // λ_c ≥ 0 at the best bound
  std::vector<double> mu;                                         // μ_k at the best bound (size n3)
  std::vector<double> penalised;                                  // w at λ (row-major n1·n2·n3)
  double lambda_sum = 0.0;                                        // Σ_c λ_c
  double lower_bound = -std::numeric_limits<double>::infinity();  // rounded up for integer costs
  double upper_bound = std::numeric_limits<double>::infinity();
  std::vector<Tuple3> best_tuples;  // canonical, complete (empty if none found)
  int64_t iterations = 0;           // dual evaluations
  int rounds = 0;
  Termination termination = Termination::kIterationLimit;  // kOptimal when UB − LB is closed
};

// Adds δ to w over the members of Q(r) (each once), for a canonical n1×n2×n3 tensor.
void add_clique_penalty(const CostTensor3& b, const Tuple3& r, double delta, std::vector<double>& w);

// Σ_{s ∈ Q(r)} x_s for an assignment given by, for each i, its (j, k) (row_j[i], row_k[i]; every i
// assigned) and, for each j, its i or −1 (owner_of_j).
int clique_load(const Tuple3& r, const std::vector<int32_t>& row_j, const std::vector<int32_t>& row_k,
                const std::vector<int32_t>& owner_of_j);

// Runs the relax-and-cut from the plain relaxation `start` (its μ, incumbent and bound), with
// options' step rule, patience, min_theta, gap tolerances, local search and time limit (from t0).
CliqueRelaxation run_clique_relaxation(const CanonicalProblem3& p, const LagrangianOptions& options,
                                       const CliqueCutOptions& cuts, const LagrangianRun& start,
                                       std::chrono::steady_clock::time_point t0);

}  // namespace trackassoc
