// Jonker–Volgenant LAP: JV's initialisation (Computing 38, 1987, §4.1), then the shortest
// augmenting path in the rectangular form of Crouse (IEEE TAES 52(4) 2016, Algorithm 1 and §III) —
// see lap.hpp for the contract.
//
// Implementation notes (why it looks the way it does):
// - Initialisation (square only for the column phases): column reduction, reduction transfer, then
//   two passes of augmenting row reduction. They leave assigned rows dual feasible with tight
//   pairs, which is all the augmentation needs. On the uniform n = 1000 benchmark matrix 9 rows of
//   1000 are left to augment; on the geometric one 149.
// - Augmentation: for each free row a Dijkstra search over reduced costs c_ij − u_i − v_j finds the
//   shortest augmenting path to a free column (Crouse Alg. 1 steps 3–4); the duals are then
//   updated so that every reduced cost stays ≥ 0 and matched pairs stay tight (Crouse Eq. 14–15).
//   Only the source row may have negative reduced costs, which is harmless because all its arcs
//   leave the source.
// - Each Dijkstra step scans all columns of contiguous arrays (AVX2 when available, same result as
//   the scalar loop): a scanned column is parked with v = −inf and distance +inf, so it neither
//   relaxes nor wins, and its v is restored at the dual update. This beats an indexed list of the
//   unscanned columns (a gather per entry), since a search scans few of the columns. Ties prefer a
//   free column, which ends the search early.
// - The augmenting row reduction is an auction with ε = 0, which can cycle for a long time with
//   tiny price gaps; a budget on its chained steps bounds it (8·rows), the rest is augmented.
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
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "kernels/assignment/lap_phases.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

void LapOptions::validate() const {
  require(std::isfinite(unassigned_cost), "LapOptions.unassigned_cost",
          "must be finite, got " + std::to_string(unassigned_cost));
}

namespace {

using lap_detail::kInf;
using lap_detail::TwoSmallest;

// Work arrays of one solve, sized once.
struct LapWorkspace : lap_detail::LapState {
  std::vector<double> shortest, path, assigned, final_dist, saved_v;
  std::vector<int32_t> scanned_rows, scanned_cols;

  LapWorkspace(int32_t nr, int32_t nc)
      : LapState(nr, nc), shortest(nc), path(nc, -1.0), assigned(nc, 0.0), final_dist(nc), saved_v(nc) {
    scanned_rows.reserve(nr);
    scanned_cols.reserve(nc);
  }
};

// One Dijkstra step over all nc columns: relaxes shortest[j] with r_j = base + row[j] − v[j]
// (path[j] = i where it improves), then returns the column of the smallest (shortest[j],
// assigned[j]), the first such j, with its distance in `lowest` (ties prefer a free column, which
// ends the search early). Scanned columns take part with v = −inf and shortest = +inf, so they
// neither relax nor win; the loop runs over contiguous arrays, 4 columns per AVX2 instruction when
// available (same result as the scalar loop, which is kept for other targets).
int32_t scan_row(const double* row, double base, double i, LapWorkspace& w, int32_t nc, double& lowest) {
  double* const shortest = w.shortest.data();
  double* const path = w.path.data();
  const double* const v = w.v.data();
  const double* const assigned = w.assigned.data();
  double best_s = kInf, best_a = 2.0;
  int32_t best = -1, j = 0;
#if defined(__AVX2__)
  // Two independent sets of lane minima (columns 8k..8k+3 and 8k+4..8k+7) halve the dependency
  // chain of the running minimum; the merge below takes the smallest (s, a, j) of all eight.
  const __m256d vbase = _mm256_set1_pd(base), vi = _mm256_set1_pd(i), eight = _mm256_set1_pd(8.0);
  __m256d low[2] = {_mm256_set1_pd(kInf), _mm256_set1_pd(kInf)};
  __m256d low_a[2] = {_mm256_set1_pd(2.0), _mm256_set1_pd(2.0)};
  __m256d low_j[2] = {_mm256_set1_pd(-1.0), _mm256_set1_pd(-1.0)};
  __m256d jj[2] = {_mm256_setr_pd(0.0, 1.0, 2.0, 3.0), _mm256_setr_pd(4.0, 5.0, 6.0, 7.0)};
  for (; j + 8 <= nc; j += 8) {
    for (int h = 0; h < 2; ++h) {
      const int32_t jh = j + 4 * h;
      const __m256d r =
          _mm256_sub_pd(_mm256_add_pd(vbase, _mm256_loadu_pd(row + jh)), _mm256_loadu_pd(v + jh));
      __m256d s = _mm256_loadu_pd(shortest + jh);
      const __m256d better = _mm256_cmp_pd(r, s, _CMP_LT_OQ);
      s = _mm256_blendv_pd(s, r, better);
      _mm256_storeu_pd(shortest + jh, s);
      _mm256_storeu_pd(path + jh, _mm256_blendv_pd(_mm256_loadu_pd(path + jh), vi, better));
      const __m256d a = _mm256_loadu_pd(assigned + jh);
      const __m256d take = _mm256_or_pd(
          _mm256_cmp_pd(s, low[h], _CMP_LT_OQ),
          _mm256_and_pd(_mm256_cmp_pd(s, low[h], _CMP_EQ_OQ), _mm256_cmp_pd(a, low_a[h], _CMP_LT_OQ)));
      low[h] = _mm256_blendv_pd(low[h], s, take);
      low_a[h] = _mm256_blendv_pd(low_a[h], a, take);
      low_j[h] = _mm256_blendv_pd(low_j[h], jj[h], take);
      jj[h] = _mm256_add_pd(jj[h], eight);
    }
  }
  alignas(32) double ls[8], la[8], lj[8];
  for (int h = 0; h < 2; ++h) {
    _mm256_store_pd(ls + 4 * h, low[h]);
    _mm256_store_pd(la + 4 * h, low_a[h]);
    _mm256_store_pd(lj + 4 * h, low_j[h]);
  }
  for (int lane = 0; lane < 8; ++lane) {  // the lexicographically smallest (s, a, j) of the lanes
    const int32_t lane_j = static_cast<int32_t>(lj[lane]);
    if (lane_j < 0) continue;
    if (best < 0 || ls[lane] < best_s ||
        (ls[lane] == best_s && (la[lane] < best_a || (la[lane] == best_a && lane_j < best)))) {
      best_s = ls[lane];
      best_a = la[lane];
      best = lane_j;
    }
  }
#endif
  for (; j < nc; ++j) {
    const double r = base + row[j] - v[j];
    double s = shortest[j];
    if (r < s) {
      s = r;
      shortest[j] = r;
      path[j] = i;
    }
    if (s < best_s || (s == best_s && assigned[j] < best_a)) {
      best_s = s;
      best_a = assigned[j];
      best = j;
    }
  }
  lowest = best_s;
  return best;
}

// Dijkstra from free row `source` (Crouse Alg. 1, steps 3–4). Returns the sink column, or −1 when no
// augmenting path of finite cost exists (v is then restored). On return `min_val` is the shortest
// path length; the scanned columns keep v = −inf until the caller's dual update.
int32_t shortest_augmenting_path(const double* cost, int32_t nc, int32_t source, LapWorkspace& w,
                                 double& min_val) {
  std::fill(w.shortest.begin(), w.shortest.end(), kInf);
  w.scanned_rows.clear();
  w.scanned_cols.clear();
  min_val = 0.0;
  int32_t i = source;
  while (true) {
    w.scanned_rows.push_back(i);
    const double* const row = cost + static_cast<std::size_t>(i) * nc;
    double lowest = kInf;
    const int32_t j = scan_row(row, min_val - w.u[i], static_cast<double>(i), w, nc, lowest);
    if (!(lowest < kInf)) {  // every remaining column is unreachable: infeasible row
      for (const int32_t c : w.scanned_cols) w.v[c] = w.saved_v[c];
      return -1;
    }
    min_val = lowest;
    w.scanned_cols.push_back(j);
    w.final_dist[j] = lowest;
    w.saved_v[j] = w.v[j];
    w.v[j] = -kInf;  // out of later scans
    w.shortest[j] = kInf;
    if (w.row4col[j] == -1) return j;
    i = w.row4col[j];
  }
}

// lap_detail::TwoSmallest of the row h_j = row[j] − v[j]. The AVX2 path runs TwoSmallest's rule
// per lane and merges the lanes into the same result (the global minimum's lane gives j1; the
// second value comes from that lane's second or another lane's minimum).
TwoSmallest two_smallest(const double* row, const double* v, int32_t nc) {
  TwoSmallest t;
  int32_t j = 0;
#if defined(__AVX2__)
  if (nc >= 8) {
    const __m256d four = _mm256_set1_pd(4.0);
    __m256d u1 = _mm256_set1_pd(kInf), u2 = u1, j1 = _mm256_set1_pd(-1.0), j2 = j1;
    __m256d jj = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
    for (; j + 4 <= nc; j += 4) {
      const __m256d h = _mm256_sub_pd(_mm256_loadu_pd(row + j), _mm256_loadu_pd(v + j));
      const __m256d lt1 = _mm256_cmp_pd(h, u1, _CMP_LT_OQ);
      const __m256d lt2 = _mm256_cmp_pd(h, u2, _CMP_LT_OQ);
      u2 = _mm256_blendv_pd(_mm256_blendv_pd(u2, h, lt2), u1, lt1);
      j2 = _mm256_blendv_pd(_mm256_blendv_pd(j2, jj, lt2), j1, lt1);
      u1 = _mm256_blendv_pd(u1, h, lt1);
      j1 = _mm256_blendv_pd(j1, jj, lt1);
      jj = _mm256_add_pd(jj, four);
    }
    alignas(32) double a1[4], a2[4], b1[4], b2[4];
    _mm256_store_pd(a1, u1);
    _mm256_store_pd(a2, u2);
    _mm256_store_pd(b1, j1);
    _mm256_store_pd(b2, j2);
    int win = -1;  // lane of the global minimum, first index on ties
    for (int l = 0; l < 4; ++l)
      if (b1[l] >= 0 && (win < 0 || a1[l] < a1[win] || (a1[l] == a1[win] && b1[l] < b1[win]))) win = l;
    if (win >= 0) {
      t.u1 = a1[win];
      t.j1 = static_cast<int32_t>(b1[win]);
      t.u2 = a2[win];
      for (int l = 0; l < 4; ++l)
        if (l != win && b1[l] >= 0) t.u2 = std::min(t.u2, a1[l]);
      if (t.u2 < kInf) {  // the first index other than j1 with value u2
        double first = (a2[win] == t.u2 && b2[win] >= 0) ? b2[win] : kInf;
        for (int l = 0; l < 4; ++l)
          if (l != win && b1[l] >= 0 && a1[l] == t.u2) first = std::min(first, b1[l]);
        t.j2 = static_cast<int32_t>(first);
      }
    }
  }
#endif
  for (; j < nc; ++j) t.add(row[j] - v[j], j);
  return t;
}

// Column reduction and reduction transfer (JV §4.1, square matrices only). Column reduction sets
// v_j = min_i c_ij and assigns each column's minimum row if that row is still unassigned (columns
// in reverse order, as in JV); a column of +inf entries only keeps v_j = 0 and stays free. Reduction
// transfer then lowers v of the column of every row assigned exactly once by that row's second
// smallest reduced cost, so the row's own reduced cost equals its row dual. Rows assigned to no
// column go to `free_rows`.
void column_reduction(const double* cost, int32_t n, LapWorkspace& w) {
  // Column minima by a row-wise pass (strict <, so ties keep the first row, as JV's column scan).
  std::vector<double> col_min(n, kInf);
  std::vector<int32_t> arg_min(n, -1);
  for (int32_t i = 0; i < n; ++i) {
    const double* const row = cost + static_cast<std::size_t>(i) * n;
    for (int32_t j = 0; j < n; ++j) {
      const bool lower = row[j] < col_min[j];
      col_min[j] = lower ? row[j] : col_min[j];
      arg_min[j] = lower ? i : arg_min[j];
    }
  }
  std::vector<int32_t> matches(n, 0);
  for (int32_t j = n - 1; j >= 0; --j) {
    const int32_t i = arg_min[j];
    if (i < 0) continue;  // only +inf in this column: v_j = 0, left to the augmentation
    w.v[j] = col_min[j];
    if (++matches[i] == 1) {
      w.col4row[i] = j;
      w.row4col[j] = i;
    }
  }
  w.free_rows.clear();
  for (int32_t i = 0; i < n; ++i) {
    if (matches[i] == 0) {
      w.free_rows.push_back(i);
      continue;
    }
    if (matches[i] != 1) continue;
    // Its reduced cost at its column is 0, the row minimum, so the smallest over the other columns
    // is the second smallest of the row.
    const double second = two_smallest(cost + static_cast<std::size_t>(i) * n, w.v.data(), n).u2;
    if (second < kInf) w.v[w.col4row[i]] -= second;  // one finite entry: the reduction stays
  }
}

// Core solver for nr ≤ nc on a row-major nr×nc matrix without NaN. Fills col4row (−1 for rows
// that could not be assigned at finite cost) and returns false if any row could not be assigned.
bool solve_rectangular(const double* cost, int32_t nr, int32_t nc, bool initialise,
                       std::vector<int32_t>& col4row_out, std::vector<double>& u_out,
                       std::vector<double>& v_out, int32_t& augmented_rows) {
  LapWorkspace w(nr, nc);
  if (initialise && nr == nc) {
    column_reduction(cost, nr, w);
  } else {
    // Rectangular: v = 0 on every column, so free columns keep the largest v (the condition the
    // rectangular augmentation needs, Crouse §III); only the row reduction below applies.
    w.free_rows.resize(nr);
    for (int32_t i = 0; i < nr; ++i) w.free_rows[i] = i;
  }
  if (initialise) {
    int64_t budget = lap_detail::row_reduction_budget(nr);
    auto smallest = [&](int32_t i) {
      return two_smallest(cost + static_cast<std::size_t>(i) * nc, w.v.data(), nc);
    };
    for (int phase = 0; phase < 2 && !w.free_rows.empty(); ++phase)
      lap_detail::augmenting_row_reduction(w, smallest, budget);
    // Explicit row duals of the assigned rows: their pairs are tight.
    for (int32_t i = 0; i < nr; ++i) {
      const int32_t j = w.col4row[i];
      if (j >= 0) w.u[i] = cost[static_cast<std::size_t>(i) * nc + j] - w.v[j];
    }
  }
  bool feasible = true;
  augmented_rows = static_cast<int32_t>(w.free_rows.size());
  for (int32_t j = 0; j < nc; ++j) w.assigned[j] = w.row4col[j] >= 0 ? 1.0 : 0.0;
  for (const int32_t cur : w.free_rows) {
    double min_val = 0.0;
    const int32_t sink = shortest_augmenting_path(cost, nc, cur, w, min_val);
    if (sink < 0) {
      feasible = false;  // the row stays unassigned; the duals were not touched
      continue;
    }
    for (const int32_t c : w.scanned_cols) w.v[c] = w.saved_v[c];  // unpark the scanned columns
    w.assigned[sink] = 1.0;
    lap_detail::augment(w, cur, sink, min_val, w.scanned_rows, w.scanned_cols, w.final_dist.data(),
                        [&](int32_t j) { return static_cast<int32_t>(w.path[j]); });
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
  bool feasible = true;
  if (nr > 0)
    feasible = solve_rectangular(matrix, nr, nc, options.initialise, col4row, u, v, result.augmented_rows);
  lap_detail::assemble_result(result, feasible, col4row, u, v, nr, nc, transpose, options, at);
  return result;
}

}  // namespace trackassoc
