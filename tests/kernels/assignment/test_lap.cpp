// Tests of the Jonker–Volgenant LAP (kernels/assignment/lap.hpp) against brute-force enumeration,
// hand-worked small cases, an independent Hungarian reference (larger random and adversarial
// matrices) and the plain shortest augmenting path (LapOptions::initialise = false), with the LP dual
// certificate (feasibility, complementary slackness, strong duality) checked on every solve.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Brute force: minimum over all matchings. When `allow_unassigned`, any partial matching with
// `u` per unassigned row and column; otherwise only matchings of min(rows, cols) pairs.
// Returns +inf when no matching of finite cost exists.
struct BruteForce {
  const std::vector<double>& c;
  int rows, cols;
  bool allow_unassigned;
  double u;
  std::vector<char> used;
  double best = kInf;

  void run() {
    used.assign(cols, 0);
    recurse(0, 0.0, 0);
  }
  void recurse(int r, double acc, int assigned) {
    if (r == rows) {
      if (allow_unassigned) {
        acc += u * static_cast<double>((rows - assigned) + (cols - assigned));
      } else if (assigned != std::min(rows, cols)) {
        return;
      }
      best = std::min(best, acc);
      return;
    }
    // Leave row r unassigned: always allowed with allow_unassigned; otherwise only when rows > cols
    // and enough rows remain to fill the columns.
    if (allow_unassigned || (rows - r - 1) >= (std::min(rows, cols) - assigned))
      recurse(r + 1, acc, assigned);
    for (int col = 0; col < cols; ++col) {
      if (used[col]) continue;
      const double x = c[static_cast<std::size_t>(r) * cols + col];
      if (std::isinf(x)) continue;
      used[col] = 1;
      recurse(r + 1, acc + x, assigned + 1);
      used[col] = 0;
    }
  }
};

double brute_force(const std::vector<double>& c, int rows, int cols, bool allow_unassigned = false,
                   double u = 0.0) {
  BruteForce bf{c, rows, cols, allow_unassigned, u, {}};
  bf.run();
  return bf.best;
}

// Largest finite |entry|: the scale of rounding errors in the duals.
double scale_of(const std::vector<double>& c) {
  double m = 0.0;
  for (double x : c)
    if (std::isfinite(x)) m = std::max(m, std::abs(x));
  return m;
}

// The returned matching is consistent, and its recomputed cost equals result.cost.
void check_consistent(const LapResult& r, const std::vector<double>& c, int rows, int cols,
                      const LapOptions& o) {
  ASSERT_EQ(static_cast<int>(r.row_to_col.size()), rows);
  ASSERT_EQ(static_cast<int>(r.col_to_row.size()), cols);
  double sum = 0.0;
  int assigned = 0;
  for (int i = 0; i < rows; ++i) {
    const int j = r.row_to_col[i];
    if (j < 0) continue;
    ASSERT_LT(j, cols);
    ASSERT_EQ(r.col_to_row[j], i);
    ASSERT_FALSE(std::isinf(c[static_cast<std::size_t>(i) * cols + j]));
    sum += c[static_cast<std::size_t>(i) * cols + j];
    ++assigned;
  }
  int assigned_cols = 0;
  for (int j = 0; j < cols; ++j) assigned_cols += (r.col_to_row[j] >= 0);
  ASSERT_EQ(assigned, assigned_cols);
  if (!r.feasible) return;
  if (o.allow_unassigned) {
    sum += o.unassigned_cost * ((rows - assigned) + (cols - assigned));
  } else {
    ASSERT_EQ(assigned, std::min(rows, cols));
    // Dual feasibility and strong duality (the certificate branch and bound relies on).
    ASSERT_EQ(static_cast<int>(r.row_dual.size()), rows);
    ASSERT_EQ(static_cast<int>(r.col_dual.size()), cols);
    double dual_sum = 0.0;
    for (int i = 0; i < rows; ++i) dual_sum += r.row_dual[i];
    for (int j = 0; j < cols; ++j) dual_sum += r.col_dual[j];
    EXPECT_NEAR(dual_sum, r.cost, 1e-9 * std::max(1.0, scale_of(c)) * std::max(rows, cols));
    const double tol = 1e-9 * std::max(1.0, scale_of(c));
    int violations = 0;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        violations += !(r.row_dual[i] + r.col_dual[j] <= c[static_cast<std::size_t>(i) * cols + j] + tol);
    EXPECT_EQ(violations, 0) << "dual infeasible entries";
    // Complementary slackness: assigned pairs tight; an unassigned row/column of the longer side has
    // dual 0 (its constraint Σ x ≤ 1 is slack).
    for (int i = 0; i < rows; ++i) {
      const int j = r.row_to_col[i];
      if (j >= 0)
        EXPECT_NEAR(r.row_dual[i] + r.col_dual[j], c[static_cast<std::size_t>(i) * cols + j], tol);
      else
        EXPECT_EQ(r.row_dual[i], 0.0);
    }
    for (int j = 0; j < cols; ++j)
      if (r.col_to_row[j] < 0) {
        EXPECT_EQ(r.col_dual[j], 0.0);
      }
    if (rows <= cols) {
      for (int j = 0; j < cols; ++j) EXPECT_LE(r.col_dual[j], 0.0);
    }
    if (rows > cols) {
      for (int i = 0; i < rows; ++i) EXPECT_LE(r.row_dual[i], 0.0);
    }
  }
  EXPECT_NEAR(sum, r.cost, 1e-9 * std::max(1.0, std::abs(sum)));
}

std::vector<double> random_matrix(CounterRng& rng, int rows, int cols, double p_forbidden, bool integer) {
  std::vector<double> c(static_cast<std::size_t>(rows) * cols);
  for (auto& x : c) {
    x = integer ? static_cast<double>(rng.uniform_int(10)) - 3.0 : rng.uniform(-1.0, 5.0);
    if (p_forbidden > 0 && rng.uniform() < p_forbidden) x = kInf;
  }
  return c;
}

TEST(Lap, KnownSmallCases) {
  // scipy.optimize.linear_sum_assignment's documentation example: optimum 5 (0→1, 1→0, 2→2).
  const std::vector<double> a{4, 1, 3, 2, 0, 5, 3, 2, 2};
  const auto r = solve_lap(a, 3, 3);
  EXPECT_TRUE(r.feasible);
  EXPECT_DOUBLE_EQ(r.cost, 5.0);
  EXPECT_EQ(r.row_to_col, (std::vector<int32_t>{1, 0, 2}));

  // 2×3 by hand: rows {0,1}, (0,2)=1 and (1,0)=2 → 3, better than (0,0)+(1,2) = 1+... etc.
  const std::vector<double> b{5, 9, 1, 2, 8, 7};
  const auto rb = solve_lap(b, 2, 3);
  EXPECT_DOUBLE_EQ(rb.cost, 3.0);
  EXPECT_EQ(rb.row_to_col, (std::vector<int32_t>{2, 0}));
  EXPECT_EQ(rb.col_to_row, (std::vector<int32_t>{1, -1, 0}));

  // The 3×2 transpose of b: same optimum, columns → rows swapped.
  const std::vector<double> bt{5, 2, 9, 8, 1, 7};
  const auto rbt = solve_lap(bt, 3, 2);
  EXPECT_DOUBLE_EQ(rbt.cost, 3.0);
  EXPECT_EQ(rbt.row_to_col, (std::vector<int32_t>{1, -1, 0}));

  // Forbidden entries forcing the anti-diagonal: cost 1 + 1 + 1.
  const std::vector<double> f{kInf, kInf, 1, kInf, 1, kInf, 1, kInf, kInf};
  const auto rf = solve_lap(f, 3, 3);
  EXPECT_TRUE(rf.feasible);
  EXPECT_DOUBLE_EQ(rf.cost, 3.0);
  EXPECT_EQ(rf.row_to_col, (std::vector<int32_t>{2, 1, 0}));

  // Infeasible: rows 0 and 1 can only use column 0.
  const std::vector<double> g{1, kInf, 2, kInf};
  const auto rg = solve_lap(g, 2, 2);
  EXPECT_FALSE(rg.feasible);
  EXPECT_TRUE(std::isinf(rg.cost));
  EXPECT_EQ((rg.row_to_col[0] == 0) + (rg.row_to_col[1] == 0), 1);  // one of them got column 0

  // allow_unassigned by hand: pairing (0,0) costs 10 > 2·u = 6, so both stay unassigned (cost 6);
  // (1,1) costs 1 < 6 and is kept. Total 6 + 1.
  const std::vector<double> h{10, kInf, kInf, 1};
  const auto rh = solve_lap(h, 2, 2, LapOptions{true, 3.0});
  EXPECT_TRUE(rh.feasible);
  EXPECT_DOUBLE_EQ(rh.cost, 7.0);
  EXPECT_EQ(rh.row_to_col, (std::vector<int32_t>{-1, 1}));
}

TEST(Lap, EmptyAndDegenerate) {
  const auto r0 = solve_lap({}, 0, 0);
  EXPECT_TRUE(r0.feasible);
  EXPECT_EQ(r0.cost, 0.0);
  const auto r1 = solve_lap({}, 0, 4);
  EXPECT_EQ(r1.col_to_row, (std::vector<int32_t>(4, -1)));
  const auto r2 = solve_lap({}, 3, 0, LapOptions{true, 1.5});
  EXPECT_DOUBLE_EQ(r2.cost, 4.5);
  const std::vector<double> one{-2.5};
  EXPECT_DOUBLE_EQ(solve_lap(one, 1, 1).cost, -2.5);
}

TEST(Lap, BadInputIsRejected) {
  const std::vector<double> nan_cost{1, std::nan(""), 2, 3};
  EXPECT_THROW(solve_lap(nan_cost, 2, 2), InputError);
  const std::vector<double> minus_inf{1, -kInf, 2, 3};
  EXPECT_THROW(solve_lap(minus_inf, 2, 2), InputError);
  const std::vector<double> three{1, 2, 3};
  EXPECT_THROW(solve_lap(three, 2, 2), InputError);
  EXPECT_THROW(solve_lap({}, -1, 0), InputError);
  EXPECT_THROW(solve_lap(three, 1, 3, LapOptions{true, kInf}), InputError);
}

// Square and rectangular in both orientations, real and integer costs (ties), with and without
// forbidden entries.
TEST(Lap, MatchesBruteForce) {
  CounterRng rng(20261123, 1);
  int checked = 0, infeasible = 0;
  for (int rows = 1; rows <= 8; ++rows)
    for (int cols = 1; cols <= 8; ++cols) {
      const int trials = (rows * cols > 36) ? 3 : 8;
      for (int t = 0; t < trials; ++t) {
        const double p_forbidden = (t % 3 == 0) ? 0.0 : (t % 3 == 1 ? 0.3 : 0.6);
        const auto c = random_matrix(rng, rows, cols, p_forbidden, t % 2 == 0);
        const auto r = solve_lap(c, rows, cols);
        const double expected = brute_force(c, rows, cols);
        SCOPED_TRACE(testing::Message() << rows << "x" << cols << " trial " << t);
        check_consistent(r, c, rows, cols, LapOptions{});
        if (std::isinf(expected)) {
          EXPECT_FALSE(r.feasible);
          ++infeasible;
        } else {
          EXPECT_TRUE(r.feasible);
          EXPECT_NEAR(r.cost, expected, 1e-9);
        }
        ++checked;
      }
    }
  EXPECT_GT(infeasible, 5);  // the forbidden-entry cases did exercise infeasibility
  EXPECT_GT(checked, 300);
}

TEST(Lap, AllowUnassignedMatchesBruteForce) {
  CounterRng rng(20261123, 2);
  for (int rows = 1; rows <= 6; ++rows)
    for (int cols = 1; cols <= 6; ++cols)
      for (int t = 0; t < 4; ++t) {
        const auto c = random_matrix(rng, rows, cols, t >= 2 ? 0.4 : 0.0, t % 2 == 0);
        const double u = (t % 2 == 0) ? 1.0 : rng.uniform(0.0, 2.5);
        const LapOptions o{true, u};
        const auto r = solve_lap(c, rows, cols, o);
        SCOPED_TRACE(testing::Message() << rows << "x" << cols << " trial " << t);
        EXPECT_TRUE(r.feasible);
        check_consistent(r, c, rows, cols, o);
        EXPECT_NEAR(r.cost, brute_force(c, rows, cols, true, u), 1e-9);
      }
}

// A larger case whose optimum is known by construction: a permutation with cost 0 and every other
// entry ≥ 1, so the unique optimum is that permutation.
TEST(Lap, PlantedPermutation) {
  CounterRng rng(7, 3);
  const int n = 300;
  std::vector<int32_t> perm(n);
  for (int i = 0; i < n; ++i) perm[i] = i;
  rng.shuffle(std::span<int32_t>(perm));
  std::vector<double> c(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      c[static_cast<std::size_t>(i) * n + j] = (perm[i] == j) ? 0.0 : 1.0 + rng.uniform();
  const auto r = solve_lap(c, n, n);
  EXPECT_EQ(r.cost, 0.0);
  EXPECT_EQ(r.row_to_col, perm);
}

// Independent reference: the O(n²·m) Hungarian method with potentials (Kuhn–Munkres in the form of
// e-maxx.ru "Hungarian algorithm", 1-based), for rows ≤ cols; rows > cols by transposing. Forbidden
// entries become a penalty larger than any finite matching, so an optimum using one means infeasible.
// Returns the optimum or +inf.
double hungarian(const std::vector<double>& c, int rows, int cols) {
  if (rows > cols) {
    std::vector<double> t(c.size());
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        t[static_cast<std::size_t>(j) * rows + i] = c[static_cast<std::size_t>(i) * cols + j];
    return hungarian(t, cols, rows);
  }
  const int n = rows, m = cols;
  double finite_sum = 1.0;
  for (double x : c)
    if (std::isfinite(x)) finite_sum += std::abs(x);
  const double penalty = 4.0 * finite_sum;
  auto a = [&](int i, int j) {
    const double x = c[static_cast<std::size_t>(i - 1) * m + (j - 1)];
    return std::isfinite(x) ? x : penalty;
  };
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, kInf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0, j) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  double total = 0.0;
  for (int j = 1; j <= m; ++j) {
    if (p[j] == 0) continue;
    const double x = c[static_cast<std::size_t>(p[j] - 1) * m + (j - 1)];
    if (!std::isfinite(x)) return kInf;
    total += x;
  }
  return total;
}

// Solves with and without the JV initialisation, checks both certificates and compares both optima
// with the Hungarian reference (exactly when `exact`: integer costs, so every sum is exact).
void check_against_reference(const std::vector<double>& c, int rows, int cols, bool exact) {
  const double expected = hungarian(c, rows, cols);
  const double tol = exact ? 0.0 : 1e-9 * std::max(1.0, scale_of(c)) * std::max(rows, cols);
  for (const bool init : {true, false}) {
    LapOptions o;
    o.initialise = init;
    const auto r = solve_lap(c, rows, cols, o);
    SCOPED_TRACE(testing::Message() << rows << "x" << cols << (init ? " JV" : " plain SAP"));
    check_consistent(r, c, rows, cols, o);
    if (std::isinf(expected)) {
      EXPECT_FALSE(r.feasible);
    } else {
      ASSERT_TRUE(r.feasible);
      EXPECT_NEAR(r.cost, expected, tol);
    }
    if (!init) {
      EXPECT_EQ(r.augmented_rows, std::min(rows, cols));
    }
  }
}

TEST(Lap, MatchesHungarianOnRandomMatrices) {
  CounterRng rng(20261202, 4);
  const int sizes[][2] = {{1, 1},   {1, 7},   {7, 1},   {12, 12},  {20, 35},
                          {35, 20}, {50, 50}, {64, 65}, {120, 120}};
  for (const auto& sz : sizes) {
    const int rows = sz[0], cols = sz[1];
    for (int t = 0; t < 6; ++t) {
      const double p_forbidden = (t < 2) ? 0.0 : (t < 4 ? 0.3 : 0.8);
      check_against_reference(random_matrix(rng, rows, cols, p_forbidden, t % 2 == 0), rows, cols,
                              t % 2 == 0);
    }
  }
}

// Matrices built to stress the initialisation: all ties, two values, Latin squares (every row and
// column has the same multiset), low-rank i·j, |i − j|, integers over 12 decades (no rounding in
// double, sums exact), price wars (every row prefers the same few columns by tiny gaps), a single
// finite entry per row, and squared distances of clustered points (many near-ties).
TEST(Lap, MatchesHungarianOnAdversarialMatrices) {
  CounterRng rng(20261202, 5);
  for (const int n : {1, 2, 5, 17, 40, 90}) {
    for (const int cols : {n, n + 3}) {
      const std::size_t size = static_cast<std::size_t>(n) * cols;
      std::vector<double> c(size);
      auto fill = [&](auto f) {
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < cols; ++j) c[static_cast<std::size_t>(i) * cols + j] = f(i, j);
      };
      SCOPED_TRACE(testing::Message() << "n " << n << " cols " << cols);
      fill([](int, int) { return 3.0; });
      check_against_reference(c, n, cols, true);
      fill([&](int, int) { return static_cast<double>(rng.uniform_int(2)); });
      check_against_reference(c, n, cols, true);
      fill([&](int i, int j) { return static_cast<double>((i + j) % cols); });
      check_against_reference(c, n, cols, true);
      fill([](int i, int j) { return static_cast<double>(i) * j; });
      check_against_reference(c, n, cols, true);
      fill([](int i, int j) { return -static_cast<double>(i) * j; });
      check_against_reference(c, n, cols, true);
      fill([](int i, int j) { return std::abs(static_cast<double>(i - j)); });
      check_against_reference(c, n, cols, true);
      fill([&](int, int) { return std::floor(rng.uniform() * std::pow(10.0, rng.uniform_int(13))); });
      check_against_reference(c, n, cols, true);
      fill([&](int, int) { return std::floor(rng.uniform() * 1e12) - 5e11; });
      check_against_reference(c, n, cols, true);
      fill([&](int i, int j) { return j < 3 ? 1e-9 * i + 1e-12 * rng.uniform() : 1.0 + rng.uniform(); });
      check_against_reference(c, n, cols, false);
      fill([&](int i, int j) { return j < 3 ? static_cast<double>(i % 2) : 1000.0 + j; });
      check_against_reference(c, n, cols, true);
      fill([&](int i, int j) { return j == (i * 7) % cols ? static_cast<double>(i) : kInf; });
      check_against_reference(c, n, cols, true);
      // A few finite entries per row; with n rows on few columns, often infeasible.
      fill([&](int i, int j) {
        return (j == i % 3 || rng.uniform() < 0.05) ? static_cast<double>(rng.uniform_int(5)) : kInf;
      });
      check_against_reference(c, n, cols, true);
      std::vector<double> ax(n), ay(n), bx(cols), by(cols);
      for (int i = 0; i < n; ++i) {
        ax[i] = std::floor(rng.uniform() * 3) + 1e-3 * rng.uniform();
        ay[i] = rng.uniform();
      }
      for (int j = 0; j < cols; ++j) {
        bx[j] = std::floor(rng.uniform() * 3) + 1e-3 * rng.uniform();
        by[j] = rng.uniform();
      }
      fill([&](int i, int j) {
        const double dx = ax[i] - bx[j], dy = ay[i] - by[j];
        return dx * dx + dy * dy;
      });
      check_against_reference(c, n, cols, false);
    }
  }
}

// allow_unassigned at sizes past brute force: against the Hungarian method on the usual padded
// (rows + cols)² matrix [[C, U], [U', 0]] with U diagonal (the non-assignment cost) and +inf off it.
TEST(Lap, AllowUnassignedMatchesPaddedHungarian) {
  CounterRng rng(20261202, 6);
  for (const auto& sz : {std::pair{30, 30}, std::pair{25, 40}, std::pair{40, 25}, std::pair{60, 60}}) {
    const int rows = sz.first, cols = sz.second, n = rows + cols;
    for (int t = 0; t < 4; ++t) {
      const auto c = random_matrix(rng, rows, cols, t >= 2 ? 0.5 : 0.0, t % 2 == 0);
      const double u = t % 2 == 0 ? 1.0 : rng.uniform(0.0, 2.0);
      std::vector<double> padded(static_cast<std::size_t>(n) * n, kInf);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j)
          padded[static_cast<std::size_t>(i) * n + j] = c[static_cast<std::size_t>(i) * cols + j];
      for (int i = 0; i < rows; ++i) padded[static_cast<std::size_t>(i) * n + cols + i] = u;
      for (int j = 0; j < cols; ++j) padded[static_cast<std::size_t>(rows + j) * n + j] = u;
      for (int i = rows; i < n; ++i)
        for (int j = cols; j < n; ++j) padded[static_cast<std::size_t>(i) * n + j] = 0.0;
      const double expected = hungarian(padded, n, n);
      for (const bool init : {true, false}) {
        LapOptions o{true, u};
        o.initialise = init;
        const auto r = solve_lap(c, rows, cols, o);
        SCOPED_TRACE(testing::Message() << rows << "x" << cols << " trial " << t << (init ? " JV" : " SAP"));
        EXPECT_TRUE(r.feasible);
        check_consistent(r, c, rows, cols, o);
        EXPECT_NEAR(r.cost, expected, 1e-9 * n);
      }
    }
  }
}

// The initialisation does the bulk of the work on a random square matrix: after column reduction,
// reduction transfer and two row-reduction phases, well under half the rows need an augmenting
// path (JV 1987 report the same on uniform costs), with the same optimum as the plain augmentation.
TEST(Lap, InitialisationAssignsMostRows) {
  CounterRng rng(20261202, 7);
  const int n = 200;
  const auto c = random_matrix(rng, n, n, 0.0, false);
  const auto jv = solve_lap(c, n, n);
  LapOptions plain;
  plain.initialise = false;
  const auto sap = solve_lap(c, n, n, plain);
  EXPECT_LT(jv.augmented_rows, n / 2);
  EXPECT_EQ(sap.augmented_rows, n);
  EXPECT_NEAR(jv.cost, sap.cost, 1e-9 * n);
  EXPECT_NEAR(jv.cost, hungarian(c, n, n), 1e-9 * n);
}

}  // namespace
}  // namespace trackassoc
