// 2-D linear assignment (LAP) by the Jonker–Volgenant shortest augmenting path algorithm.
//
// Algorithm: Jonker & Volgenant, "A shortest augmenting path algorithm for dense and sparse linear
// assignment problems", Computing 38 (1987) 325–340; the rectangular form follows Crouse, "On
// implementing 2D rectangular assignment algorithms", IEEE TAES 52(4) 2016 (the algorithm behind
// scipy.optimize.linear_sum_assignment). Dense, O(n²·m) worst case for an n×m matrix, n ≤ m.
//
// Rectangular matrices assign min(rows, cols) pairs. With allow_unassigned, a row or column may
// also stay unassigned at `unassigned_cost` each (solved by padding with dummy rows/columns).
// Infeasible (some row of the shorter side cannot be matched through finite entries): feasible =
// false, cost = +inf, and the returned partial matching leaves those rows unassigned.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace trackassoc {

struct LapOptions {
  bool allow_unassigned = false;
  double unassigned_cost = 0.0;  // cost of leaving one row or one column unassigned
  void validate() const;
};

struct LapResult {
  std::vector<int32_t> row_to_col;  // -1 = unassigned
  std::vector<int32_t> col_to_row;  // -1 = unassigned
  double cost = 0.0;                // Σ assigned costs + unassigned_cost per unassigned row/column
  bool feasible = true;             // false when only +inf entries could complete the assignment
  // LP dual solution (filled when feasible and !allow_unassigned): row_dual[r] + col_dual[c] ≤ c_rc
  // for every entry, the duals of the longer side are ≤ 0, and Σ row_dual + Σ col_dual = cost. So
  // for any sub-matrix the sums of the remaining duals are a valid lower bound (used by
  // branch and bound).
  std::vector<double> row_dual, col_dual;
};

// cost[r·cols + c], row-major. Entries may be +inf (forbidden); NaN is an InputError.
LapResult solve_lap(std::span<const double> cost, int32_t rows, int32_t cols, const LapOptions& options = {});

}  // namespace trackassoc
