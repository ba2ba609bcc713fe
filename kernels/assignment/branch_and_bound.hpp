// Exact 3-D assignment by depth-first branch and bound with Lagrangian bounds (DESIGN §4.5): the
// project's ground truth for small n.
//
// Works on the canonical problem (assignment_canonical.hpp: n1 ≤ n2 ≤ n3, complete tuples).
//  - Root: the Lagrangian relaxation with local search (lagrangian_relaxation.hpp) gives an
//    incumbent and the multipliers μ_k of the relaxed dimension k (its bound is the LP bound).
//    Unless that closes the gap (or the cube is padded for a dummy index), the relax-and-cut of
//    clique_cuts.hpp adds the clique facets Σ_{s ∈ Q(r)} x_s ≤ 1 (Balas–Saltzman 1989) with multipliers λ ≥
//    0, which lifts the bound above the LP's (on DecompLib ap3 n = 30–50 to the optimum), and improves the
//    incumbent. When it lifts the rounded bound the search runs on the penalised costs w = b + Σ_c λ_c 1[s ∈
//    Q(r_c)] with the constant −Σλ (valid at every node: a relaxed cut has slack ≥ 0 in every completion);
//    else on b.
//  - Node: some tuples are fixed; the free i, j, k form a smaller 3-D problem. Its bound is the
//    Lagrangian bound of Pattipati Eq. 14 restricted to the free indices,
//        Σ_fixed w + LAP_{I×J}( min_{k∈K} w_ijk + μ_k ) − Σ_{k∈K} μ_k − Σ λ,
//    sharpened by a few subgradient steps on μ per node (Polyak, target = incumbent; λ stays at
//    the root's). With integer costs the bound is rounded up. A node whose bound reaches the
//    incumbent is pruned.
//  - Branching: on the free i with the fewest surviving children, over its (j, k). The LAP's dual
//    certificate (u, v) gives every child a bound without solving anything:
//        bound(child i→(j,k)) ≥ bound(node) + w_ijk + μ_k − u_i − v_j
//    (the dual stays feasible for the child's smaller LAP, whose costs can only grow). Children are
//    visited best-first by that bound, and children at or above the incumbent are never created.
//    A relaxed solution that satisfies the relaxed constraints is a candidate incumbent.
//  - Targeted passes (integer costs): the search first prunes at root bound + 1, i.e. looks only
//    for a solution costing the root bound; a pass that completes without one proves the optimum
//    ≥ bound + 1 and the next pass looks one higher, until the target reaches the incumbent (the
//    plain search). With a tight root bound and a poor incumbent (ap3.50.4: bound 271 = optimum,
//    incumbent 275) the first pass finds the optimum in a few nodes.
// Worst case exponential. Every DecompLib ap3 instance (n ≤ 50) and Balas–Saltzman instance
// (n ≤ 26) is proven optimal in about 2 s or less (bench/bench_3d_solvers.cpp, against CBC in
// bench/cbc_3d.py).
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
  int search_passes = 0;  // targeted passes of the search (see above)
};

Solution3 solve_branch_and_bound3(const CostTensor3& cost, const BranchAndBoundOptions& options = {},
                                  BranchAndBoundStats* stats = nullptr);

}  // namespace trackassoc
