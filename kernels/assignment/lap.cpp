// Jonker–Volgenant shortest augmenting path LAP, rectangular form of Crouse (IEEE TAES 52(4) 2016,
// Algorithm 1 and §III) — see lap.hpp for the contract.
//
// Implementation notes (why it looks the way it does):
// - One row is added at a time. For the new free row a Dijkstra search over reduced costs
//   c_ij − u_i − v_j finds the shortest augmenting path to a free column (Crouse Alg. 1 steps 3–4);
//   the duals are then updated so that every reduced cost stays ≥ 0 and matched pairs stay tight
//   (Crouse Eq. 14–15). Only the source row may have negative reduced costs, which is harmless
//   because all its arcs leave the source.
// - The unscanned columns are kept in a compact list (`remaining`) so that each Dijkstra step
//   touches only live columns; ties prefer a free column, which ends the search early.
// - All work arrays are allocated once per solve; the augmentation loop allocates nothing.
// - rows > cols is solved on the transpose, so the search always runs over the longer side.
// - allow_unassigned: leaving row r and column c both unassigned costs 2·u, assigning them costs
//   c_rc, so the problem is a rectangular LAP on c'_rc = min(c_rc − 2u, 0) in which every row is
//   assigned; pairs with c'_rc = 0 (c_rc ≥ 2u, or +inf) are then released. This is equivalent to
//   the usual (rows+cols)² padding with dummy rows and columns, at the cost of the original size.
#include "kernels/assignment/lap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"

namespace trackassoc {

void LapOptions::validate() const {
  require(std::isfinite(unassigned_cost), "LapOptions.unassigned_cost",
          "must be finite, got " + std::to_string(unassigned_cost));
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Work arrays of one solve, sized once.
struct LapWorkspace {
  std::vector<double> u, v, shortest;
  std::vector<int32_t> path, col4row, row4col, remaining, scanned_rows, scanned_cols;
  std::vector<char> row_scanned;

  LapWorkspace(int32_t nr, int32_t nc)
      : u(nr, 0.0),
        v(nc, 0.0),
        shortest(nc),
        path(nc, -1),
        col4row(nr, -1),
        row4col(nc, -1),
        remaining(nc),
        row_scanned(nr, 0) {
    scanned_rows.reserve(nr);
    scanned_cols.reserve(nc);
  }
};

// Dijkstra from free row `source` (Crouse Alg. 1, steps 3–4). Returns the sink column, or −1 when no
// augmenting path of finite cost exists. On return `min_val` is the shortest path length.
int32_t shortest_augmenting_path(const double* cost, int32_t nc, int32_t source, LapWorkspace& w,
                                 double& min_val) {
  int32_t num_remaining = nc;
  // Reverse order, as in scipy's rectangular_lsap.cpp, so results match scipy's on ties.
  for (int32_t it = 0; it < nc; ++it) w.remaining[it] = nc - it - 1;
  std::fill(w.shortest.begin(), w.shortest.end(), kInf);
  w.scanned_rows.clear();
  w.scanned_cols.clear();

  double* const shortest = w.shortest.data();
  int32_t* const remaining = w.remaining.data();
  int32_t* const path = w.path.data();
  const int32_t* const row4col = w.row4col.data();
  const double* const v = w.v.data();

  min_val = 0.0;
  int32_t i = source;
  while (true) {
    w.row_scanned[i] = 1;
    w.scanned_rows.push_back(i);
    const double* const row = cost + static_cast<std::size_t>(i) * nc;
    const double base = min_val - w.u[i];
    int32_t best_index = -1;
    double lowest = kInf;
    for (int32_t it = 0; it < num_remaining; ++it) {
      const int32_t j = remaining[it];
      const double r = base + row[j] - v[j];
      if (r < shortest[j]) {
        path[j] = i;
        shortest[j] = r;
      }
      const double s = shortest[j];
      if (s < lowest || (s == lowest && row4col[j] == -1)) {
        lowest = s;
        best_index = it;
      }
    }
    min_val = lowest;
    if (!(min_val < kInf)) return -1;  // every remaining column is unreachable: infeasible row
    const int32_t j = remaining[best_index];
    w.scanned_cols.push_back(j);
    remaining[best_index] = remaining[--num_remaining];
    if (row4col[j] == -1) return j;
    i = row4col[j];
  }
}

// Core solver for nr ≤ nc on a row-major nr×nc matrix without NaN. Fills col4row (−1 for rows
// that could not be assigned at finite cost) and returns false if any row could not be assigned.
bool solve_rectangular(const double* cost, int32_t nr, int32_t nc, std::vector<int32_t>& col4row_out,
                       std::vector<double>& u_out, std::vector<double>& v_out) {
  LapWorkspace w(nr, nc);
  bool feasible = true;
  for (int32_t cur = 0; cur < nr; ++cur) {
    double min_val = 0.0;
    const int32_t sink = shortest_augmenting_path(cost, nc, cur, w, min_val);
    if (sink < 0) {
      // The row stays unassigned; the duals were not touched, so the other rows proceed normally.
      for (int32_t r : w.scanned_rows) w.row_scanned[r] = 0;
      feasible = false;
      continue;
    }
    // Dual update (Crouse Eq. 14–15): keeps reduced costs ≥ 0 and matched pairs tight.
    w.u[cur] += min_val;
    for (int32_t r : w.scanned_rows) {
      if (r != cur) w.u[r] += min_val - w.shortest[w.col4row[r]];
      w.row_scanned[r] = 0;
    }
    for (int32_t c : w.scanned_cols) w.v[c] -= min_val - w.shortest[c];
    // Augment along the path back to the source row.
    int32_t j = sink;
    while (true) {
      const int32_t i = w.path[j];
      w.row4col[j] = i;
      std::swap(w.col4row[i], j);
      if (i == cur) break;
    }
  }
  col4row_out = std::move(w.col4row);
  u_out = std::move(w.u);
  v_out = std::move(w.v);
  return feasible;
}

}  // namespace

LapResult solve_lap(std::span<const double> cost, int32_t rows, int32_t cols, const LapOptions& options) {
  options.validate();
  require(rows >= 0 && cols >= 0, "solve_lap",
          "negative matrix size " + std::to_string(rows) + "x" + std::to_string(cols));
  const std::size_t n_entries = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  require(cost.size() == n_entries, "solve_lap",
          "cost has " + std::to_string(cost.size()) +
              " entries, expected rows*cols = " + std::to_string(n_entries));
  for (std::size_t e = 0; e < n_entries; ++e)
    if (std::isnan(cost[e]) || cost[e] == -kInf)
      throw InputError("solve_lap: cost entry (" + std::to_string(e / (cols ? cols : 1)) + ", " +
                       std::to_string(e % (cols ? cols : 1)) + ") is " + std::to_string(cost[e]) +
                       "; expected a finite number or +inf (forbidden)");

  LapResult result;
  result.row_to_col.assign(rows, -1);
  result.col_to_row.assign(cols, -1);
  result.cost = 0.0;
  result.feasible = true;

  const bool transpose = rows > cols;
  const int32_t nr = transpose ? cols : rows;
  const int32_t nc = transpose ? rows : cols;
  auto at = [&](int32_t r, int32_t c) {  // entry of the (possibly transposed) nr×nc problem
    return transpose ? cost[static_cast<std::size_t>(c) * cols + r]
                     : cost[static_cast<std::size_t>(r) * cols + c];
  };

  // Build the working matrix only when it differs from the input (transpose or unassigned shift).
  std::vector<double> work;
  const double* matrix = cost.data();
  const double two_u = 2.0 * options.unassigned_cost;
  if (transpose || options.allow_unassigned) {
    work.resize(n_entries);
    for (int32_t r = 0; r < nr; ++r)
      for (int32_t c = 0; c < nc; ++c) {
        const double x = at(r, c);
        work[static_cast<std::size_t>(r) * nc + c] = options.allow_unassigned ? std::min(x - two_u, 0.0) : x;
      }
    matrix = work.data();
  }

  std::vector<int32_t> col4row;
  std::vector<double> u, v;
  if (nr > 0) result.feasible = solve_rectangular(matrix, nr, nc, col4row, u, v);
  if (result.feasible && !options.allow_unassigned) {
    // Free columns keep v = 0 and v only decreases (Crouse Eq. 15), so v ≤ 0 on the longer side.
    u.resize(nr, 0.0);
    v.resize(nc, 0.0);
    result.row_dual = transpose ? std::move(v) : std::move(u);
    result.col_dual = transpose ? std::move(u) : std::move(v);
  }

  for (int32_t r = 0; r < nr; ++r) {
    const int32_t c = col4row[r];
    if (c < 0) continue;
    const double x = at(r, c);
    if (options.allow_unassigned && !(x < two_u)) continue;  // not worth assigning: release the pair
    const int32_t row = transpose ? c : r;
    const int32_t col = transpose ? r : c;
    result.row_to_col[row] = col;
    result.col_to_row[col] = row;
    result.cost += x;
  }
  if (options.allow_unassigned) {
    int64_t unassigned = 0;
    for (int32_t c : result.row_to_col) unassigned += (c < 0);
    for (int32_t r : result.col_to_row) unassigned += (r < 0);
    result.cost += options.unassigned_cost * static_cast<double>(unassigned);
  }
  if (!result.feasible) result.cost = kInf;
  return result;
}

}  // namespace trackassoc
