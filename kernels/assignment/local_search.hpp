// Local search for the 3-D assignment (docs/design.md §4.5): fix two dimensions of the current solution and
// re-solve the third by a 2-D LAP, cycling over the three choices until none improves.
//
// With the pairs (i, j) of the current tuples fixed, choosing k for each pair is a rectangular LAP
// of the m pairs against all n3 indices, cost b_ijk (the recovery step of the relaxation algorithm,
// seed 000 §4; Pattipati et al. 1992). The same for (i, k) → j and (j, k) → i. Each move is exact
// over its neighbourhood, so the objective never increases; the search stops at a point where no
// single-dimension re-assignment helps ("converged"). O(rounds · 3 · m²·n) time.
//
// It polishes any solver's result: solve_local_search3 takes a starting assignment in the original
// indices (complete or not: missing indices are filled with free ones first).
#pragma once

#include <vector>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

struct LocalSearchOptions {
  int max_rounds = 100;  // a round tries all three moves
  void validate() const;
};

struct LocalSearchStats {
  int rounds = 0;
  bool converged = false;  // stopped because no move improved (not at max_rounds)
};

// Polishes canonical tuples in place (a complete assignment of the canonical tensor: n1 tuples).
LocalSearchStats polish_canonical(const CostTensor3& canonical, std::vector<Tuple3>& tuples,
                                  const LocalSearchOptions& options);

// Original-index tuples → a complete canonical assignment (inverse of to_original, then completed
// with free indices in order, so any partial start is accepted).
std::vector<Tuple3> to_canonical(const CanonicalProblem3& p, const std::vector<Tuple3>& original);

// Polishes `start` (original indices). The summary reports the polished objective, termination
// kConverged (or kIterationLimit at max_rounds), and `sweeps` = rounds.
Solution3 solve_local_search3(const CostTensor3& cost, const std::vector<Tuple3>& start,
                              const LocalSearchOptions& options = {});

}  // namespace trackassoc
