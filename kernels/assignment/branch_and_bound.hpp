// Exact 3-D assignment by depth-first branch and bound with Lagrangian bounds (docs/design.md §4.5): the
// project's ground truth for small n.
//
// The scheme of Balas & Saltzman, "An algorithm for the three-index assignment problem", Oper. Res.
// 39(1), 1991: branch and bound on a Lagrangian bound strengthened by facet inequalities.
// Works on the canonical problem (assignment_canonical.hpp: n1 ≤ n2 ≤ n3, complete tuples).
//  - Root: the Lagrangian relaxation with local search (lagrangian_relaxation.hpp) gives an
//    incumbent and the multipliers μ_k of the relaxed dimension k (its bound is the LP bound).
//    Unless that closes the gap (or the cube is padded for a dummy index), the relax-and-cut of
//    clique_cuts.hpp adds the clique facets Σ_{s ∈ Q(r)} x_s ≤ 1 (Balas–Saltzman 1989) with multipliers λ ≥
//    0, which lifts the bound above the LP's (on DecompLib ap3 n = 30–50 to the optimum), and improves the
//    incumbent. When it lifts the unrounded bound (an LAP at each root's multipliers decides) the
//    search runs on the penalised costs w = b + Σ_c λ_c 1[s ∈ Q(r_c)] with the constant −Σλ (valid
//    at every node: a relaxed cut has slack ≥ 0 in every completion); else on b. Lifting only the
//    unrounded bound matters (ap3.50.4: 270.003 → 270.965, both 271 rounded): the gap left for
//    reduced-cost fixing drops from 0.997 to 0.035 and every node's bound keeps the cuts.
//  - Reduced-cost fixing (Nemhauser & Wolsey, Integer and Combinatorial Optimization, 1988, §II.5):
//    with the root's LAP duals (u, v), rc_s = w_s + μ_k − u_i − v_j ≥ 0 and every assignment
//    containing s costs ≥ L + rc_s (L the root's raw bound). Each pass sets w_s = +∞ for the tuples
//    whose L + rc_s cannot beat its target (ap3.50.4: 124 684 of 125 000). O(n1·n2·n3) per pass.
//  - Node: some tuples are fixed; the free i, j, k form a smaller 3-D problem. Its bound is the
//    Lagrangian bound of Pattipati Eq. 14 restricted to the free indices,
//        Σ_fixed w + LAP_{I×J}( min_{k∈K} w_ijk + μ_k ) − Σ_{k∈K} μ_k − Σ λ + Σ_{dead c} λ_c,
//    sharpened by a few subgradient steps on μ per node (Polyak, target = incumbent; λ stays at
//    the root's). A cut is dead when no member is fixed and none is free with finite w: its load
//    is 0 in every completion, so its λ_c is given back (O(|I| + |J| + |K|) per cut with λ_c > 0).
//    With integer costs the bound is rounded up. A node whose bound reaches the incumbent is pruned.
//  - Branching: the LAP's dual certificate (u, v) gives every child tuple a bound without solving
//    anything:
//        bound(child (i, j, k)) ≥ bound(node) + w_ijk + μ_k − u_i − v_j
//    (the dual stays feasible for the child's smaller LAP, whose costs can only grow). The surviving
//    children (below the incumbent) are counted per free i, and per free j and k while those must
//    all be used; an index with none prunes the node, else the branch is on the index with the
//    fewest (most constrained first), its children visited best-first by that bound. O(r·|J|·|K|).
//    A relaxed solution that satisfies the relaxed constraints is a candidate incumbent.
//  - Targeted passes (integer costs): the search first prunes at root bound + 1, i.e. looks only
//    for a solution costing the root bound; a pass that completes without one proves the optimum
//    ≥ bound + 1 and the next pass looks one higher, until the target reaches the incumbent (the
//    plain search).
// Worst case exponential. Every DecompLib ap3 instance (n ≤ 50) and Balas–Saltzman instance
// (n ≤ 26) is proven optimal (docs/performance.md, "exact branch and bound"; bench/bench_3d_solvers.cpp,
// against CBC in bench/cbc_3d.py).
//
// Termination: kOptimal with lower_bound = objective when the search completes; kTimeLimit (or
// kIterationLimit at max_nodes) with the best incumbent and a valid global lower bound (the least
// bound of the unexplored nodes, and the target of an interrupted targeted pass).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/clique_cuts.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"

namespace trackassoc {

struct BranchAndBoundOptions {
  double time_limit_s = 60.0;
  int64_t max_nodes = int64_t{1} << 40;
  int node_subgradient_iterations = 8;  // subgradient steps per node to sharpen its bound
  bool reduced_cost_fixing = true;      // fix tuples by their root reduced cost in every pass
  LagrangianOptions root;               // root relaxation; local_search is forced on
  CliqueCutOptions cuts;                // root relax-and-cut with clique facets (max_rounds 0: off)
  void validate() const;
};

// What the proof took, beside the summary (whose iterations = nodes and message say the same).
struct BranchAndBoundStats {
  double root_bound = -std::numeric_limits<double>::infinity();  // after the clique cuts
  int64_t nodes = 0;
  std::size_t cuts = 0;  // clique cuts in the pool
  int cut_rounds = 0;
  int search_passes = 0;          // targeted passes of the search (see above)
  int64_t fixed_tuples = 0;       // tuples fixed to 0 by root reduced costs in the first pass
  bool penalised_search = false;  // the search ran on the clique-penalised costs
};

Solution3 solve_branch_and_bound3(const CostTensor3& cost, const BranchAndBoundOptions& options = {},
                                  BranchAndBoundStats* stats = nullptr);

}  // namespace trackassoc
