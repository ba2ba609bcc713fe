// Tests of the sparse LAP (kernels/assignment/lap_sparse.hpp): the same optimum as the dense
// solve_lap on the matrix with +inf off the candidate lists (the dense solver is itself checked
// against brute force and a Hungarian reference in test_lap.cpp), and an LP certificate of its own:
// a matching on candidates whose cost equals the dual objective Σu + Σv with u_i + v_j ≤ c_ij on
// every candidate, which proves optimality independently of any other solver.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A CSR matrix and its dense twin (+inf off the candidates).
struct Csr {
  int32_t rows = 0, cols = 0;
  std::vector<int32_t> start{0}, col;
  std::vector<double> cost, dense;
  SparseCostView view() const { return {rows, cols, start, col, cost}; }
};

// Each entry is a candidate with probability `density`; candidates of a row in shuffled order.
Csr random_csr(CounterRng& rng, int32_t rows, int32_t cols, double density, bool integer) {
  Csr m;
  m.rows = rows;
  m.cols = cols;
  m.dense.assign(static_cast<std::size_t>(rows) * cols, kInf);
  std::vector<int32_t> order(cols);
  for (int32_t r = 0; r < rows; ++r) {
    for (int32_t c = 0; c < cols; ++c) order[c] = c;
    rng.shuffle(std::span<int32_t>(order));
    for (const int32_t c : order) {
      if (!(rng.uniform() < density)) continue;
      const double x = integer ? static_cast<double>(rng.uniform_int(6)) : rng.uniform(-1.0, 4.0);
      m.col.push_back(c);
      m.cost.push_back(x);
      m.dense[static_cast<std::size_t>(r) * cols + c] = x;
    }
    m.start.push_back(static_cast<int32_t>(m.col.size()));
  }
  return m;
}

// The matching uses candidates only and costs what it says; when feasible and !allow_unassigned,
// the duals certify it: feasible on every candidate, tight on assigned pairs, 0 on the unassigned
// columns/rows of the longer side (≤ 0 there), and Σu + Σv = cost.
void check_certificate(const LapResult& r, const Csr& m, const LapOptions& o) {
  ASSERT_EQ(r.row_to_col.size(), static_cast<std::size_t>(m.rows));
  ASSERT_EQ(r.col_to_row.size(), static_cast<std::size_t>(m.cols));
  double total = 0.0;
  int assigned = 0;
  for (int32_t i = 0; i < m.rows; ++i) {
    const int32_t j = r.row_to_col[i];
    if (j < 0) continue;
    ASSERT_EQ(r.col_to_row[j], i);
    const double x = m.dense[static_cast<std::size_t>(i) * m.cols + j];
    ASSERT_TRUE(std::isfinite(x)) << "assigned a non-candidate";
    total += x;
    ++assigned;
  }
  if (!r.feasible) return;
  if (o.allow_unassigned) {
    total += o.unassigned_cost * static_cast<double>(m.rows + m.cols - 2 * assigned);
    EXPECT_NEAR(total, r.cost, 1e-9 * (1 + m.rows + m.cols));
    return;
  }
  EXPECT_EQ(assigned, std::min(m.rows, m.cols));
  EXPECT_NEAR(total, r.cost, 1e-9 * (1 + m.rows + m.cols));
  ASSERT_EQ(r.row_dual.size(), static_cast<std::size_t>(m.rows));
  ASSERT_EQ(r.col_dual.size(), static_cast<std::size_t>(m.cols));
  double objective = 0.0;
  for (const double x : r.row_dual) objective += x;
  for (const double x : r.col_dual) objective += x;
  EXPECT_NEAR(objective, r.cost, 1e-8 * (1 + m.rows + m.cols));
  int infeasible_entries = 0, loose_pairs = 0;
  for (int32_t i = 0; i < m.rows; ++i)
    for (int32_t e = m.start[i]; e < m.start[i + 1]; ++e) {
      const double slack = m.cost[e] - r.row_dual[i] - r.col_dual[m.col[e]];
      infeasible_entries += slack < -1e-9;
      if (r.row_to_col[i] == m.col[e]) loose_pairs += std::abs(slack) > 1e-9;
    }
  EXPECT_EQ(infeasible_entries, 0);
  EXPECT_EQ(loose_pairs, 0);
  const bool wide = m.rows <= m.cols;  // the longer side: columns (square: columns too)
  for (int32_t j = 0; j < m.cols && wide; ++j) {
    EXPECT_LE(r.col_dual[j], 0.0);
    if (r.col_to_row[j] < 0) {
      EXPECT_EQ(r.col_dual[j], 0.0);
    }
  }
  for (int32_t i = 0; i < m.rows && !wide; ++i) {
    EXPECT_LE(r.row_dual[i], 0.0);
    if (r.row_to_col[i] < 0) {
      EXPECT_EQ(r.row_dual[i], 0.0);
    }
  }
}

TEST(SparseLap, MatchesDenseAndCertifiesOptimality) {
  CounterRng rng(20261202, 11);
  int infeasible = 0, checked = 0;
  const int32_t sizes[][2] = {{1, 1},   {1, 6},   {6, 1},     {8, 8},    {15, 22},
                              {22, 15}, {60, 60}, {150, 170}, {170, 150}};
  for (const auto& sz : sizes)
    for (const double density : {0.05, 0.2, 0.5, 1.0})
      for (const bool integer : {true, false}) {
        const Csr m = random_csr(rng, sz[0], sz[1], density, integer);
        const LapResult dense = solve_lap(m.dense, m.rows, m.cols);
        for (const bool init : {true, false}) {
          LapOptions o;
          o.initialise = init;
          const LapResult sparse = solve_sparse_lap(m.view(), o);
          SCOPED_TRACE(testing::Message() << sz[0] << "x" << sz[1] << " density " << density
                                          << (integer ? " integer" : " real") << (init ? " JV" : " SAP"));
          check_certificate(sparse, m, o);
          EXPECT_EQ(sparse.feasible, dense.feasible);
          if (dense.feasible) {
            EXPECT_NEAR(sparse.cost, dense.cost, 1e-9 * (1 + m.rows));
          }
          infeasible += !sparse.feasible;
          ++checked;
        }
      }
  EXPECT_GT(infeasible, 10);  // the low densities did exercise infeasibility
  EXPECT_GT(checked, 100);
}

TEST(SparseLap, AllowUnassignedMatchesDense) {
  CounterRng rng(20261202, 12);
  for (const auto& sz :
       {std::pair{1, 1}, std::pair{7, 7}, std::pair{30, 45}, std::pair{45, 30}, std::pair{120, 120}})
    for (const double density : {0.05, 0.3, 1.0}) {
      const Csr m = random_csr(rng, sz.first, sz.second, density, density == 0.3);
      for (const double u : {0.0, 0.7, 2.5}) {
        LapOptions o{true, u};
        const LapResult dense = solve_lap(m.dense, m.rows, m.cols, o);
        const LapResult sparse = solve_sparse_lap(m.view(), o);
        SCOPED_TRACE(testing::Message()
                     << sz.first << "x" << sz.second << " density " << density << " u " << u);
        EXPECT_TRUE(sparse.feasible);
        check_certificate(sparse, m, o);
        EXPECT_NEAR(sparse.cost, dense.cost, 1e-9 * (1 + m.rows + m.cols));
      }
    }
}

// The dispatcher (solve_gated_lap): the dense solver's optimum whichever solver it picks, on
// matrices large enough for the sparse one, below and above the density threshold, square and
// rectangular, with and without unassigned rows; the sparse pick certified by the duals.
TEST(SparseLap, GatedDispatcherMatchesDense) {
  CounterRng rng(20261202, 13);
  for (const auto& sz : {std::pair{120, 120}, std::pair{100, 160}, std::pair{160, 110}})
    for (const double density : {0.005, 0.015, 0.05, 0.3})
      for (const bool unassigned : {false, true}) {
        const Csr m = random_csr(rng, sz.first, sz.second, density, false);
        LapOptions o{unassigned, 0.8};
        const LapResult dense = solve_lap(m.dense, m.rows, m.cols, o);
        const LapResult gated = solve_gated_lap(m.dense, m.rows, m.cols, o);
        GatedLapOptions never;
        never.max_density = 0.0;
        const LapResult forced_dense = solve_gated_lap(m.dense, m.rows, m.cols, o, never);
        SCOPED_TRACE(testing::Message() << sz.first << "x" << sz.second << " density " << density
                                        << (unassigned ? " unassigned allowed" : ""));
        EXPECT_EQ(gated.feasible, dense.feasible);
        if (dense.feasible) {
          EXPECT_NEAR(gated.cost, dense.cost, 1e-9 * (1 + m.rows + m.cols));
        }
        EXPECT_EQ(forced_dense.row_to_col, dense.row_to_col);
        if (gated.feasible) check_certificate(gated, m, o);
      }
  GatedLapOptions bad;
  bad.max_density = 1.5;
  const std::vector<double> one{1.0};
  EXPECT_THROW(solve_gated_lap(one, 1, 1, {}, bad), InputError);
  std::vector<double> nan(200 * 200, kInf);
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solve_gated_lap(nan, 200, 200), InputError);
}

// Hand-checked: a 3×4 gate with a forced chain. Row 0 can only take column 1; row 1 prefers column 1
// (cost 0) but must move to column 2 (3); row 2 takes column 0 (1). Optimum 2 + 3 + 1 = 6.
TEST(SparseLap, KnownSmallCase) {
  const std::vector<int32_t> start{0, 1, 3, 5}, col{1, 1, 2, 0, 2};
  const std::vector<double> cost{2, 0, 3, 1, 9};
  const LapResult r = solve_sparse_lap({3, 4, start, col, cost});
  EXPECT_TRUE(r.feasible);
  EXPECT_DOUBLE_EQ(r.cost, 6.0);
  EXPECT_EQ(r.row_to_col, (std::vector<int32_t>{1, 2, 0}));
  EXPECT_EQ(r.col_to_row, (std::vector<int32_t>{2, 0, 1, -1}));
  // Rows 0 and 1 both only on column 1: infeasible, one of them keeps it.
  const std::vector<int32_t> start2{0, 1, 2}, col2{1, 1};
  const std::vector<double> cost2{1, 1};
  const LapResult r2 = solve_sparse_lap({2, 2, start2, col2, cost2});
  EXPECT_FALSE(r2.feasible);
  EXPECT_TRUE(std::isinf(r2.cost));
  EXPECT_EQ((r2.row_to_col[0] == 1) + (r2.row_to_col[1] == 1), 1);
  // Empty matrix.
  const std::vector<int32_t> zero{0};
  EXPECT_EQ(solve_sparse_lap({0, 3, zero, {}, {}}).cost, 0.0);
}

TEST(SparseLap, BadInputIsRejected) {
  const std::vector<int32_t> start{0, 2}, col{0, 0}, col_out{0, 5};
  const std::vector<double> cost{1, 2}, nan_cost{1, std::nan("")};
  EXPECT_THROW(solve_sparse_lap({1, 3, start, col, cost}), InputError);      // column twice in a row
  EXPECT_THROW(solve_sparse_lap({1, 3, start, col_out, cost}), InputError);  // column out of range
  const std::vector<int32_t> col_ok{0, 1};
  EXPECT_THROW(solve_sparse_lap({1, 3, start, col_ok, nan_cost}), InputError);
  const std::vector<int32_t> short_start{0};
  EXPECT_THROW(solve_sparse_lap({1, 3, short_start, col_ok, cost}), InputError);  // offsets missing
  const std::vector<int32_t> bad_end{0, 1};
  EXPECT_THROW(solve_sparse_lap({1, 3, bad_end, col_ok, cost}), InputError);  // nnz mismatch
  const std::vector<int32_t> decreasing{0, 2, 1};
  EXPECT_THROW(solve_sparse_lap({2, 3, decreasing, col_ok, cost}), InputError);
  EXPECT_NO_THROW(solve_sparse_lap({1, 3, start, col_ok, cost}));
}

}  // namespace
}  // namespace trackassoc
