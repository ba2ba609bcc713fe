// Shared helpers of the 3-D solver tests: the benchmark instance paths and checks every solver
// result must pass (valid assignment, recomputed cost = objective), plus a brute-force optimum.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "io/instance_text.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc::testing_support {

inline std::string bench_dir() { return std::string(TRACKASSOC_SHARED_DIR) + "/benchmarks/3dap"; }
inline std::string decomplib(const std::string& name) { return bench_dir() + "/decomplib/" + name; }
inline std::string balas_saltzman(const std::string& name) { return bench_dir() + "/balas-saltzman/" + name; }

// Every solver result: a valid assignment whose recomputed cost equals the reported objective.
inline void expect_consistent(const CostTensor3& b, const Solution3& s) {
  EXPECT_TRUE(is_valid_assignment(b, s.tuples));
  EXPECT_TRUE(s.summary.feasible);
  const double recomputed = assignment_cost(b, s.tuples);
  EXPECT_NEAR(recomputed, s.summary.objective, 1e-9 * std::max(1.0, std::abs(recomputed)));
}

// Brute-force optimum of a small 3-D assignment with dummy semantics of assignment_cost: every
// index of every dimension is either in a complete tuple or left out at miss_cost per missing
// index of its tuple. With miss_cost = inf: min(n) complete tuples. Exponential; n ≤ 5.
inline double brute_force_optimum(const CostTensor3& b) {
  const bool miss = std::isfinite(b.miss_cost);
  const double m = b.miss_cost;
  std::vector<char> uj(b.n2, 0), uk(b.n3, 0);
  double best = std::numeric_limits<double>::infinity();
  const int need = std::min({b.n1, b.n2, b.n3});
  std::function<void(int, double, int)> rec = [&](int i, double acc, int complete) {
    if (i == b.n1) {
      if (!miss) {
        if (complete == need) best = std::min(best, acc);
        return;
      }
      // Leftover j's and k's: pair as many as possible (one missing index each), rest alone (two).
      int rj = 0, rk = 0;
      for (char u : uj) rj += !u;
      for (char u : uk) rk += !u;
      const int pairs = std::min(rj, rk);
      best = std::min(best, acc + m * (pairs + 2.0 * (rj + rk - 2 * pairs)));
      return;
    }
    // Without dummies, row i may stay out only if enough rows remain (n1 > need).
    if (miss) {
      rec(i + 1, acc + 2 * m, complete);  // (i, -, -)
      for (int j = 0; j < b.n2; ++j)
        if (!uj[j]) {
          uj[j] = 1;
          rec(i + 1, acc + m, complete);  // (i, j, -)
          uj[j] = 0;
        }
      for (int k = 0; k < b.n3; ++k)
        if (!uk[k]) {
          uk[k] = 1;
          rec(i + 1, acc + m, complete);  // (i, -, k)
          uk[k] = 0;
        }
    } else if (b.n1 - i - 1 >= need - complete) {
      rec(i + 1, acc, complete);
    }
    for (int j = 0; j < b.n2; ++j) {
      if (uj[j]) continue;
      uj[j] = 1;
      for (int k = 0; k < b.n3; ++k) {
        if (uk[k]) continue;
        uk[k] = 1;
        rec(i + 1, acc + b.at(i, j, k), complete + 1);
        uk[k] = 0;
      }
      uj[j] = 0;
    }
  };
  rec(0, 0.0, 0);
  return best;
}

// Brute force, written independently of the solvers: the lowest free index of the first sensor
// with a free index joins every possible combination of free indices or dummies of the others.
inline double brute_force_sd(const CostTensorSD& c) {
  const int32_t S = c.dims();
  std::vector<std::vector<char>> used(S);
  for (int32_t s = 0; s < S; ++s) used[s].assign(c.n[s], 0);
  double best = std::numeric_limits<double>::infinity();
  std::vector<int32_t> t(S);
  std::function<void(double)> rec = [&](double acc) {
    int32_t s0 = -1, i0 = -1;
    for (int32_t s = 0; s < S && s0 < 0; ++s)
      for (int32_t i = 0; i < c.n[s]; ++i)
        if (!used[s][i]) {
          s0 = s;
          i0 = i;
          break;
        }
    if (s0 < 0) {
      best = std::min(best, acc);
      return;
    }
    std::vector<int32_t> choice(S, kNoTrack);
    std::function<void(int32_t)> pick = [&](int32_t q) {
      if (q == S) {
        const double v = c.at(choice);
        if (!std::isfinite(v)) return;
        for (int32_t r = 0; r < S; ++r)
          if (choice[r] >= 0) used[r][choice[r]] = 1;
        rec(acc + v);
        for (int32_t r = 0; r < S; ++r)
          if (choice[r] >= 0) used[r][choice[r]] = 0;
        return;
      }
      if (q == s0) {
        choice[q] = i0;
        pick(q + 1);
        return;
      }
      choice[q] = kNoTrack;
      pick(q + 1);
      if (q < s0) return;  // sensors before s0 are fully used
      for (int32_t i = 0; i < c.n[q]; ++i)
        if (!used[q][i]) {
          choice[q] = i;
          pick(q + 1);
        }
      choice[q] = kNoTrack;
    };
    pick(0);
  };
  rec(0.0);
  return best;
}

// A solution of the S-D problem c certified against its optimum: valid, its objective the cost of
// its tuples, the bound at most the optimum, the objective within the reported gap of it.
inline void expect_certified_sd(const CostTensorSD& c, const SolutionSD& s, double optimum) {
  ASSERT_TRUE(s.summary.feasible);
  EXPECT_TRUE(is_valid_assignment_sd(c, s.tuples));
  const double tol = 1e-5 * std::max(1.0, std::abs(optimum));
  EXPECT_NEAR(assignment_cost_sd(c, s.tuples), s.summary.objective, tol);
  EXPECT_LE(s.summary.lower_bound, optimum + tol) << "invalid lower bound";
  EXPECT_GE(s.summary.objective, optimum - tol);
  EXPECT_LE(s.summary.objective - optimum, s.summary.abs_gap + tol);
}

}  // namespace trackassoc::testing_support
