// Sparse Jonker–Volgenant LAP with a heap Dijkstra — see lap_sparse.hpp for the contract.
//
// Implementation notes:
// - The input is copied once into the problem actually solved (rows ≤ columns): finite candidates
//   only; the transpose when rows > cols; with allow_unassigned the shifted candidates c − 2u < 0
//   plus one dummy column per row at 0 (a row left unassigned), which needs no transpose.
// - Row reduction and the dual update and path flip are lap_phases.hpp's, shared with the dense
//   solver; only the row scans differ (candidates instead of all columns).
// - The Dijkstra heap holds (distance, column assigned?, column) with lazy deletion; ties pop free
//   columns first, which ends the search early, then the lower index (deterministic). Only the
//   columns a search touched are reset afterwards, so one augmentation costs O(E_s log E_s) for
//   the E_s candidates of the rows it scans.
#include "kernels/assignment/lap_sparse.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kernels/assignment/lap_phases.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

using lap_detail::kInf;

void SparseCostView::validate() const {
  require(rows >= 0 && cols >= 0, "SparseCostView",
          "negative matrix size " + std::to_string(rows) + "x" + std::to_string(cols));
  require(row_start.size() == static_cast<std::size_t>(rows) + 1, "SparseCostView.row_start",
          "has " + std::to_string(row_start.size()) +
              " offsets, expected rows + 1 = " + std::to_string(rows + 1));
  require(row_start[0] == 0, "SparseCostView.row_start",
          "must start at 0, got " + std::to_string(row_start[0]));
  // Per-entry checks build their message only on failure (they run on every solve).
  for (int32_t r = 0; r < rows; ++r)
    if (row_start[r + 1] < row_start[r])
      throw InputError("SparseCostView.row_start: decreases at row " + std::to_string(r) + " (" +
                       std::to_string(row_start[r]) + " then " + std::to_string(row_start[r + 1]) + ")");
  const std::size_t nnz = static_cast<std::size_t>(row_start[rows]);
  require(col.size() == nnz && cost.size() == nnz, "SparseCostView",
          "row_start ends at " + std::to_string(nnz) + " but col has " + std::to_string(col.size()) +
              " and cost " + std::to_string(cost.size()) + " entries");
  std::vector<int32_t> seen(cols, -1);  // last row that had each column
  for (int32_t r = 0; r < rows; ++r)
    for (int32_t e = row_start[r]; e < row_start[r + 1]; ++e) {
      auto fail = [&](const std::string& what) {
        throw InputError("SparseCostView entry " + std::to_string(e) + " (row " + std::to_string(r) +
                         "): " + what);
      };
      if (col[e] < 0 || col[e] >= cols)
        fail("column " + std::to_string(col[e]) + " outside [0, " + std::to_string(cols) + ")");
      if (seen[col[e]] == r) fail("column " + std::to_string(col[e]) + " appears twice in the row");
      seen[col[e]] = r;
      if (std::isnan(cost[e]) || cost[e] == -kInf)
        fail("cost is " + std::to_string(cost[e]) + "; expected a finite number or +inf (absent)");
    }
}

namespace {

// The problem solved: nr ≤ nc rows in CSR, with each entry's cost in the solved form (`cost`) and
// as the caller gave it (`original`, for the result).
struct SparseProblem {
  int32_t nr = 0, nc = 0;
  std::vector<int32_t> start{0}, col;
  std::vector<double> cost, original;
  void add(int32_t j, double c, double orig) {
    col.push_back(j);
    cost.push_back(c);
    original.push_back(orig);
  }
  void end_row() { start.push_back(static_cast<int32_t>(col.size())); }
  // Original cost of (r, c); the pair is a candidate.
  double original_of(int32_t r, int32_t c) const {
    for (int32_t e = start[r]; e < start[r + 1]; ++e)
      if (col[e] == c) return original[e];
    return kInf;
  }
};

SparseProblem build_problem(const SparseCostView& m, const LapOptions& options, bool transpose) {
  SparseProblem p;
  const double two_u = 2.0 * options.unassigned_cost;
  if (options.allow_unassigned) {
    p.nr = m.rows;
    p.nc = m.cols + m.rows;
    for (int32_t r = 0; r < m.rows; ++r) {
      for (int32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e)
        if (m.cost[e] < two_u) p.add(m.col[e], m.cost[e] - two_u, m.cost[e]);
      p.add(m.cols + r, 0.0, kInf);  // the row's dummy column: left unassigned
      p.end_row();
    }
    return p;
  }
  if (!transpose) {
    p.nr = m.rows;
    p.nc = m.cols;
    for (int32_t r = 0; r < m.rows; ++r) {
      for (int32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e)
        if (m.cost[e] < kInf) p.add(m.col[e], m.cost[e], m.cost[e]);
      p.end_row();
    }
    return p;
  }
  // Transpose: counting sort of the finite entries by column.
  p.nr = m.cols;
  p.nc = m.rows;
  p.start.assign(m.cols + 1, 0);
  for (int32_t e = 0; e < m.row_start[m.rows]; ++e)
    if (m.cost[e] < kInf) ++p.start[m.col[e] + 1];
  for (int32_t c = 0; c < m.cols; ++c) p.start[c + 1] += p.start[c];
  p.col.resize(p.start[m.cols]);
  p.cost.resize(p.start[m.cols]);
  std::vector<int32_t> next(p.start.begin(), p.start.end() - 1);
  for (int32_t r = 0; r < m.rows; ++r)
    for (int32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e)
      if (m.cost[e] < kInf) {
        const int32_t at = next[m.col[e]]++;
        p.col[at] = r;
        p.cost[at] = m.cost[e];
      }
  p.original = p.cost;
  return p;
}

struct HeapItem {
  double d;
  int32_t assigned, j;
  // std::push_heap builds a max-heap: "less" = later in (d, assigned, j) order.
  bool operator<(const HeapItem& o) const {
    if (d != o.d) return d > o.d;
    if (assigned != o.assigned) return assigned > o.assigned;
    return j > o.j;
  }
};

struct SparseWorkspace : lap_detail::LapState {
  std::vector<double> dist, final_dist;
  std::vector<int32_t> pred, touched, scanned_rows, scanned_cols;
  std::vector<char> done;
  std::vector<HeapItem> heap;
  SparseWorkspace(int32_t nr, int32_t nc)
      : LapState(nr, nc), dist(nc, kInf), final_dist(nc), pred(nc, -1), done(nc, 0) {}
};

// Heap Dijkstra from free row `source` over the candidates (Crouse Alg. 1, steps 3–4 on a sparse
// graph). Returns the sink column, or −1 when no augmenting path exists; `min_val` is the shortest
// path length.
int32_t sparse_augmenting_path(const SparseProblem& p, int32_t source, SparseWorkspace& w, double& min_val) {
  w.scanned_rows.clear();
  w.scanned_cols.clear();
  w.heap.clear();
  auto relax = [&](int32_t i, double base) {
    w.scanned_rows.push_back(i);
    for (int32_t e = p.start[i]; e < p.start[i + 1]; ++e) {
      const int32_t j = p.col[e];
      if (w.done[j]) continue;
      const double r = base + p.cost[e] - w.v[j];
      if (!(r < w.dist[j])) continue;
      if (w.dist[j] == kInf) w.touched.push_back(j);
      w.dist[j] = r;
      w.pred[j] = i;
      w.heap.push_back({r, w.row4col[j] >= 0 ? 1 : 0, j});
      std::push_heap(w.heap.begin(), w.heap.end());
    }
  };
  relax(source, -w.u[source]);
  int32_t sink = -1;
  while (!w.heap.empty()) {
    std::pop_heap(w.heap.begin(), w.heap.end());
    const HeapItem top = w.heap.back();
    w.heap.pop_back();
    if (w.done[top.j] || top.d > w.dist[top.j]) continue;  // stale entry
    w.done[top.j] = 1;
    w.final_dist[top.j] = top.d;
    w.scanned_cols.push_back(top.j);
    min_val = top.d;
    if (w.row4col[top.j] < 0) {
      sink = top.j;
      break;
    }
    const int32_t i = w.row4col[top.j];
    relax(i, top.d - w.u[i]);
  }
  for (const int32_t j : w.touched) {
    w.dist[j] = kInf;
    w.done[j] = 0;
  }
  w.touched.clear();
  return sink;
}

bool solve_sparse_problem(const SparseProblem& p, bool initialise, SparseWorkspace& w,
                          int32_t& augmented_rows) {
  w.free_rows.resize(p.nr);
  for (int32_t i = 0; i < p.nr; ++i) w.free_rows[i] = i;
  if (initialise) {
    int64_t budget = lap_detail::row_reduction_budget(p.nr);
    auto smallest = [&](int32_t i) {
      lap_detail::TwoSmallest t;
      for (int32_t e = p.start[i]; e < p.start[i + 1]; ++e) t.add(p.cost[e] - w.v[p.col[e]], p.col[e]);
      return t;
    };
    for (int phase = 0; phase < 2 && !w.free_rows.empty(); ++phase)
      lap_detail::augmenting_row_reduction(w, smallest, budget);
    for (int32_t i = 0; i < p.nr; ++i)  // explicit row duals of the assigned rows: tight pairs
      for (int32_t e = p.start[i]; e < p.start[i + 1]; ++e)
        if (p.col[e] == w.col4row[i]) w.u[i] = p.cost[e] - w.v[p.col[e]];
  }
  augmented_rows = static_cast<int32_t>(w.free_rows.size());
  bool feasible = true;
  for (const int32_t cur : w.free_rows) {
    double min_val = 0.0;
    const int32_t sink = sparse_augmenting_path(p, cur, w, min_val);
    if (sink < 0) {
      feasible = false;  // the row stays unassigned; the duals were not touched
      continue;
    }
    lap_detail::augment(w, cur, sink, min_val, w.scanned_rows, w.scanned_cols, w.final_dist.data(),
                        [&](int32_t j) { return w.pred[j]; });
  }
  return feasible;
}

}  // namespace

LapResult solve_sparse_lap(const SparseCostView& matrix, const LapOptions& options) {
  options.validate();
  matrix.validate();
  const bool transpose = !options.allow_unassigned && matrix.rows > matrix.cols;
  const SparseProblem p = build_problem(matrix, options, transpose);
  SparseWorkspace w(p.nr, p.nc);
  LapResult result;
  result.row_to_col.assign(matrix.rows, -1);
  result.col_to_row.assign(matrix.cols, -1);
  const bool feasible = p.nr == 0 || solve_sparse_problem(p, options.initialise, w, result.augmented_rows);
  // Problem columns past the caller's (allow_unassigned dummies) mean "unassigned".
  const int32_t real_cols = transpose ? matrix.rows : matrix.cols;
  w.v.resize(real_cols);
  lap_detail::assemble_result(result, feasible, w.col4row, w.u, w.v, p.nr, real_cols, transpose, options,
                              [&](int32_t r, int32_t c) { return p.original_of(r, c); });
  return result;
}

void GatedLapOptions::validate() const {
  require(max_density >= 0.0 && max_density <= 1.0, "max_density", "expected a fraction in [0, 1]");
  require(min_side >= 1, "min_side", "expected at least 1");
}

namespace {

// The dispatch rule of solve_gated_lap: the most finite entries for which the sparse solver runs
// (both sides ≥ min_side, at most max_density of the entries), or −1 when it never does.
double sparse_limit(int32_t rows, int32_t cols, const GatedLapOptions& g) {
  if (rows < g.min_side || cols < g.min_side || g.max_density <= 0.0) return -1.0;
  return g.max_density * static_cast<double>(rows) * static_cast<double>(cols);
}

}  // namespace

LapResult solve_gated_lap(std::span<const double> cost, int32_t rows, int32_t cols, const LapOptions& options,
                          const GatedLapOptions& gated) {
  gated.validate();
  const double limit = sparse_limit(rows, cols, gated);
  if (limit < 0.0) return solve_lap(cost, rows, cols, options);
  require(cost.size() == static_cast<std::size_t>(rows) * cols, "solve_gated_lap",
          "cost size is not rows x cols");
  std::size_t finite = 0;
  for (const double c : cost) {
    if (c < kInf) {
      if (static_cast<double>(++finite) > limit) return solve_lap(cost, rows, cols, options);
    } else if (c != kInf) {
      throw InputError("solve_gated_lap: NaN cost");
    }
  }
  std::vector<int32_t> row_start(static_cast<std::size_t>(rows) + 1, 0), col;
  std::vector<double> val;
  col.reserve(finite);
  val.reserve(finite);
  for (int32_t r = 0; r < rows; ++r) {
    const double* row = cost.data() + static_cast<std::size_t>(r) * cols;
    for (int32_t c = 0; c < cols; ++c)
      if (row[c] < kInf) col.push_back(c), val.push_back(row[c]);
    row_start[r + 1] = static_cast<int32_t>(col.size());
  }
  return solve_sparse_lap(SparseCostView{rows, cols, row_start, col, val}, options);
}

bool solve_gated_lap_is_dense(int32_t rows, int32_t cols, std::size_t finite, const GatedLapOptions& gated) {
  const double limit = sparse_limit(rows, cols, gated);
  return !(limit >= 0.0 && static_cast<double>(finite) <= limit);
}

LapResult solve_gated_lap(const SparseCostView& matrix, const LapOptions& options,
                          const GatedLapOptions& gated) {
  gated.validate();
  const double limit = sparse_limit(matrix.rows, matrix.cols, gated);
  if (limit >= 0.0 && static_cast<double>(matrix.col.size()) <= limit)
    return solve_sparse_lap(matrix, options);  // which validates the matrix
  matrix.validate();
  std::vector<double> dense(static_cast<std::size_t>(matrix.rows) * matrix.cols, kInf);
  for (int32_t r = 0; r < matrix.rows; ++r)
    for (int32_t e = matrix.row_start[r]; e < matrix.row_start[r + 1]; ++e)
      dense[static_cast<std::size_t>(r) * matrix.cols + matrix.col[e]] = matrix.cost[e];
  return solve_lap(dense, matrix.rows, matrix.cols, options);
}

}  // namespace trackassoc
