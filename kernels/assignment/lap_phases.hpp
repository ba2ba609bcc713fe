// Phases shared by the dense and the sparse LAP (lap.cpp, lap_sparse.cpp): Jonker–Volgenant's
// augmenting row reduction over any row representation, the dual update and path flip that end a
// Crouse shortest augmenting path, and the assembly of a LapResult. Internal to the two solvers.
//
// State invariant between the phases (JV 1987 §4; Crouse 2016 §III): every assigned row i is dual
// feasible, c_ij − u_i − v_j ≥ 0 on its finite entries, with equality on its own column; v only
// decreases; in the rectangular form the free columns keep v = 0, the largest value.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/assignment/lap.hpp"

namespace trackassoc::lap_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

struct LapState {
  std::vector<double> u, v;
  std::vector<int32_t> col4row, row4col, free_rows;
  LapState(int32_t nr, int32_t nc) : u(nr, 0.0), v(nc, 0.0), col4row(nr, -1), row4col(nc, -1) {
    free_rows.reserve(nr);
  }
};

// The two smallest reduced costs h_j = c_ij − v_j of a row: u1 at j1, the first index of the
// minimum, and u2 (= u1 on a tie) at j2, the first index other than j1 attaining it; −1 for +inf.
// Fed in index order: h < u1 moves (u1, j1) to (u2, j2); u1 ≤ h < u2 replaces (u2, j2).
struct TwoSmallest {
  double u1 = kInf, u2 = kInf;
  int32_t j1 = -1, j2 = -1;
  void add(double h, int32_t j) {
    if (!(h < u2)) return;
    if (h >= u1) {
      u2 = h;
      j2 = j;
    } else {
      u2 = u1;
      j2 = j1;
      u1 = h;
      j1 = j;
    }
  }
};

// Chained steps allowed to the two row-reduction passes together: bounds the ε = 0 auction, whose
// price wars with tiny gaps can otherwise run long; what is left goes to the augmentation.
inline int64_t row_reduction_budget(int32_t rows) { return 8 * static_cast<int64_t>(rows) + 64; }

// Augmenting row reduction (JV §4.1), one pass over `s.free_rows`: each free row i takes the column
// j1 of its smallest reduced cost and lowers v_j1 by the gap to the second smallest, so the pair is
// tight and row i dual feasible; the row that owned j1 becomes free and, when v_j1 strictly
// dropped, is processed next (an auction step with ε = 0). Equal minimum and second minimum: i
// takes the second column instead when j1 is owned, and the displaced row waits for the next pass.
// Every step keeps the state invariant (free columns' v untouched), so the pass may stop at any
// time; `budget` caps the chained steps. Rows left free stay in `s.free_rows`.
// `smallest(i)` returns the TwoSmallest of row i under the current v.
template <class Smallest>
void augmenting_row_reduction(LapState& s, Smallest&& smallest, int64_t& budget) {
  std::vector<int32_t>& free_rows = s.free_rows;
  const int32_t previous = static_cast<int32_t>(free_rows.size());
  int32_t k = 0, num_free = 0;
  while (k < previous) {
    const int32_t i = free_rows[k++];
    const TwoSmallest t = smallest(i);
    int32_t j1 = t.j1;
    int32_t i0 = j1 >= 0 ? s.row4col[j1] : -1;
    // No finite entry, or a single one whose column is owned: left to the augmentation phase.
    if (j1 < 0 || (t.u2 == kInf && i0 >= 0)) {
      free_rows[num_free++] = i;
      continue;
    }
    const bool dropped = t.u1 < t.u2 && t.u2 < kInf;
    if (dropped) {
      s.v[j1] -= t.u2 - t.u1;
    } else if (i0 >= 0 && t.u2 < kInf) {  // tie: the second column may be free
      j1 = t.j2;
      i0 = s.row4col[j1];
    }
    s.col4row[i] = j1;
    s.row4col[j1] = i;
    if (i0 < 0) continue;
    s.col4row[i0] = -1;
    if (dropped && budget > 0) {
      --budget;
      free_rows[--k] = i0;  // continue the chain with the displaced row
    } else {
      free_rows[num_free++] = i0;
    }
  }
  free_rows.resize(num_free);
}

// Ends a successful search from free row `cur` to free column `sink` at distance `min_val`: the
// dual update of Crouse Eq. 14–15 (reduced costs stay ≥ 0, matched pairs tight) over the rows and
// columns the search scanned, `final_dist[c]` being the distance of scanned column c, then the
// assignments flipped along the path (`row_of(j)`: the row that reached column j).
template <class RowOf>
void augment(LapState& s, int32_t cur, int32_t sink, double min_val, const std::vector<int32_t>& scanned_rows,
             const std::vector<int32_t>& scanned_cols, const double* final_dist, RowOf&& row_of) {
  s.u[cur] += min_val;
  for (const int32_t r : scanned_rows)
    if (r != cur) s.u[r] += min_val - final_dist[s.col4row[r]];
  for (const int32_t c : scanned_cols) s.v[c] -= min_val - final_dist[c];
  int32_t j = sink;
  while (true) {
    const int32_t i = row_of(j);
    s.row4col[j] = i;
    std::swap(s.col4row[i], j);
    if (i == cur) break;
  }
}

// Fills `result` (row_to_col, col_to_row sized by the caller) from the solved nr×nc problem, which is
// the caller's rows×cols problem or, when `transpose`, its transpose. `cost_of(r, c)` is the
// original cost of problem pair (r, c); problem columns c ≥ nc (dummies) mean "unassigned". With
// allow_unassigned, pairs not cheaper than 2·unassigned_cost are released and each unassigned row
// and column costs unassigned_cost. Duals (feasible and !allow_unassigned): square problems are
// shifted so that v ≤ 0, which keeps every u_i + v_j.
template <class CostOf>
void assemble_result(LapResult& result, bool feasible, const std::vector<int32_t>& col4row,
                     std::vector<double>& u, std::vector<double>& v, int32_t nr, int32_t nc, bool transpose,
                     const LapOptions& options, CostOf&& cost_of) {
  result.feasible = feasible;
  result.cost = 0.0;
  if (feasible && !options.allow_unassigned) {
    u.resize(nr, 0.0);
    v.resize(nc, 0.0);
    if (nr == nc && nr > 0) {
      const double shift = *std::max_element(v.begin(), v.end());
      for (double& x : v) x -= shift;
      for (double& x : u) x += shift;
    }
    result.row_dual = transpose ? std::move(v) : std::move(u);
    result.col_dual = transpose ? std::move(u) : std::move(v);
  }
  const double two_u = 2.0 * options.unassigned_cost;
  for (int32_t r = 0; r < static_cast<int32_t>(col4row.size()); ++r) {
    const int32_t c = col4row[r];
    if (c < 0 || c >= nc) continue;
    const double x = cost_of(r, c);
    if (options.allow_unassigned && !(x < two_u)) continue;  // not worth assigning: release the pair
    const int32_t row = transpose ? c : r;
    const int32_t col = transpose ? r : c;
    result.row_to_col[row] = col;
    result.col_to_row[col] = row;
    result.cost += x;
  }
  if (options.allow_unassigned) {
    int64_t unassigned = 0;
    for (const int32_t c : result.row_to_col) unassigned += (c < 0);
    for (const int32_t r : result.col_to_row) unassigned += (r < 0);
    result.cost += options.unassigned_cost * static_cast<double>(unassigned);
  }
  if (!feasible) result.cost = kInf;
}

}  // namespace trackassoc::lap_detail
