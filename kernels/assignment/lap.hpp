// 2-D linear assignment (LAP) by the Jonker–Volgenant algorithm: initialisation phases, then
// shortest augmenting paths.
//
// Algorithm: Jonker & Volgenant, "A shortest augmenting path algorithm for dense and sparse linear
// assignment problems", Computing 38 (1987) 325–340 (LAPJV). Square matrices start with JV's column
// reduction and reduction transfer; then two phases of augmenting row reduction (an auction with
// ε = 0 that assigns most rows cheaply); the rows still free are assigned by Dijkstra shortest
// augmenting paths over reduced costs. The augmentation and the rectangular form follow Crouse,
// "On implementing 2D rectangular assignment algorithms", IEEE TAES 52(4) 2016 (the algorithm behind
// scipy.optimize.linear_sum_assignment, which has no initialisation). Dense, O(n²·m) worst case for
// an n×m matrix, n ≤ m. On uniform costs the initialisation leaves 9 of 1000 rows to augment
// (2.5–3× less time than the plain augmentation, LapOptions::initialise = false); on geometric
// (squared-distance) costs 149 of 1000 remain, whose long searches take most of the time either way
// (about 1.05×), so the gain there is the vectorised Dijkstra scan (lap.cpp). bench/bench_lap.cpp
// measures both against the plain augmentation and scipy in one run.
//
// Rectangular matrices assign min(rows, cols) pairs; column reduction needs every column assigned,
// so it is skipped there (v starts at 0, which keeps free columns at the largest v as Crouse's
// rectangular augmentation requires) and the row reduction applies as in the square case.
// With allow_unassigned, a row or column may also stay unassigned at `unassigned_cost` each (solved
// as a LAP of the original size, see lap.cpp).
// Infeasible (some row of the shorter side cannot be matched through finite entries): feasible =
// false, cost = +inf, and the returned partial matching (of maximum cardinality) leaves those rows
// unassigned.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace trackassoc {

struct LapOptions {
  bool allow_unassigned = false;
  double unassigned_cost = 0.0;  // cost of leaving one row or one column unassigned
  // JV's initialisation phases before the augmentation (default). false: the plain shortest
  // augmenting path from zero duals, as scipy's; same optimum, kept for comparison and tests.
  bool initialise = true;
  void validate() const;
};

struct LapResult {
  std::vector<int32_t> row_to_col;  // -1 = unassigned
  std::vector<int32_t> col_to_row;  // -1 = unassigned
  double cost = 0.0;                // Σ assigned costs + unassigned_cost per unassigned row/column
  bool feasible = true;             // false when only +inf entries could complete the assignment
  int32_t augmented_rows = 0;       // rows left to the shortest augmenting path phase (the rest were
                                    // assigned by the initialisation); all rows of the shorter side
                                    // when !initialise
  // LP dual solution (filled when feasible and !allow_unassigned): row_dual[r] + col_dual[c] ≤ c_rc
  // for every entry, the duals of the longer side are ≤ 0, and Σ row_dual + Σ col_dual = cost. So
  // for any sub-matrix the sums of the remaining duals are a valid lower bound (used by
  // branch and bound).
  std::vector<double> row_dual, col_dual;
};

// cost[r·cols + c], row-major. Entries may be +inf (forbidden); NaN is an InputError.
LapResult solve_lap(std::span<const double> cost, int32_t rows, int32_t cols, const LapOptions& options = {});

}  // namespace trackassoc
