// One-pass heuristics for the 3-D assignment, the simple baselines of docs/design.md §4.5.
//
// greedy: sort all n1·n2·n3 tuples by cost and take each tuple whose indices are all still free.
//         O(N log N) for N = n1·n2·n3 (a partial sort is used).
// sequential pairwise: solve the 2-D LAP on c12(i, j) = min_k b_ijk, then a second LAP of the
//         merged pairs (i, j) against sensor 3 with cost b_ijk. O(n³) for the reductions plus two
//         JV solves. This is the "pairwise then merge" scheme the papers compare against.
#pragma once

#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

struct GreedyOptions {
  void validate() const {}
};
Solution3 solve_greedy3(const CostTensor3& cost, const GreedyOptions& options = {});

struct PairwiseOptions {
  void validate() const {}
};
Solution3 solve_pairwise3(const CostTensor3& cost, const PairwiseOptions& options = {});

}  // namespace trackassoc
