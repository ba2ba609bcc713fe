// Exact 3-D assignment by depth-first branch and bound with Lagrangian bounds (DESIGN §4.5): the
// project's ground truth for small n.
//
// Works on the canonical problem (assignment_canonical.hpp: n1 ≤ n2 ≤ n3, complete tuples).
//  - Root: the Lagrangian relaxation with local search (lagrangian_relaxation.hpp) gives the
//    incumbent and the multipliers μ_k of the relaxed dimension k.
//  - Node: some tuples are fixed; the free i, j, k form a smaller 3-D problem. Its bound is the
//    Lagrangian bound of Pattipati Eq. 14 restricted to the free indices,
//        fixed cost + LAP_{I×J}( min_{k∈K} b_ijk + μ_k ) − Σ_{k∈K} μ_k,
//    sharpened by a few subgradient steps per node (Polyak, target = incumbent). With integer
//    costs the bound is rounded up. A node whose bound reaches the incumbent is pruned.
//  - Branching: on the free i with the fewest surviving children, over its (j, k). The LAP's dual
//    certificate (u, v) gives every child a bound without solving anything:
//        bound(child i→(j,k)) ≥ bound(node) + b_ijk + μ_k − u_i − v_j
//    (the dual stays feasible for the child's smaller LAP, whose costs can only grow). Children are
//    visited best-first by that bound, and children at or above the incumbent are never created.
//  - A node whose relaxed solution satisfies the relaxed constraints is solved outright.
// Worst case exponential; Balas–Saltzman instances up to n = 26 take well under a second each
// (bench/bench_3d_solvers.cpp).
//
// Termination: kOptimal with lower_bound = objective when the search completes; kTimeLimit (or
// kIterationLimit at max_nodes) with the best incumbent and a valid global lower bound (the least
// bound of the unexplored nodes).
#pragma once

#include <cstdint>
#include <limits>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"

namespace trackassoc {

struct BranchAndBoundOptions {
  double time_limit_s = 60.0;
  int64_t max_nodes = int64_t{1} << 40;
  int node_subgradient_iterations = 8;  // subgradient steps per node to sharpen its bound
  LagrangianOptions root;               // root relaxation; local_search is forced on
  void validate() const;
};

Solution3 solve_branch_and_bound3(const CostTensor3& cost, const BranchAndBoundOptions& options = {});

}  // namespace trackassoc
