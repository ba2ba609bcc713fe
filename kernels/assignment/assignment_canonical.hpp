// The canonical form the 3-D solvers (Lagrangian relaxation, local search, branch and bound) work
// on, and the way back to the caller's indices.
//
// Canonical: sizes sorted n1 ≤ n2 ≤ n3 and every tuple complete (miss_cost = +inf), so a solution
// is exactly n1 tuples, each i used once, each j and k at most once. Relaxing the constraints of the
// largest dimension (k) then leaves a plain rectangular 2-D LAP over (i, j) (seed 000 §4's
// relaxation algorithm; Pattipati et al. 1992), and the relaxed constraints are equalities only
// when n1 = n3 (otherwise "≤ 1", whose multipliers must stay ≥ 0).
//
// Dummy index (finite CostTensor3::miss_cost, docs/design.md §4.3): each dimension d is padded with
// n_d' + n_d'' dummy indices, enough for every other index to sit in a tuple without d, to a cube
// of side M = n1 + n2 + n3. A tuple with q dummy indices costs q·miss_cost (q < 3), and an
// all-dummy tuple costs 0 (padding). Every solution of the original problem maps onto a complete
// assignment of the cube with the same cost and back, so solving the cube is exact. Memory is
// O(M³): refused with an InputError above `max_padded_elements`.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

struct CanonicalProblem3 {
  CostTensor3 tensor;                   // n1 ≤ n2 ≤ n3, miss_cost = +inf
  std::array<int, 3> original_dim{};    // canonical dimension d holds original dimension original_dim[d]
  std::array<int32_t, 3> original_n{};  // sizes of the original (unpadded) tensor, original order
  bool padded = false;                  // dummies were added (finite miss_cost)
  bool integer_costs = false;           // every entry is an integer: bounds may be rounded up
  // Relaxed (k) constraints are equalities (n1 = n3), so their multipliers are free in sign.
  bool k_equality() const { return tensor.n1 == tensor.n3; }
};

CanonicalProblem3 make_canonical(const CostTensor3& b,
                                 std::size_t max_padded_elements = std::size_t{1} << 27);

// Canonical tuples (complete, canonical order) → original order; dummy indices become kNoTrack
// and all-dummy tuples are dropped.
std::vector<Tuple3> to_original(const CanonicalProblem3& p, const std::vector<Tuple3>& canonical);

// Fills objective (recomputed from the tuples with assignment_cost), feasible, and the gaps
// from `lower_bound` (NaN: no bound). gap = (objective − bound) / max(|objective|, 1e-9).
void finish_summary(const CostTensor3& original, const std::vector<Tuple3>& tuples, double lower_bound,
                    SolverSummary& summary);

}  // namespace trackassoc
