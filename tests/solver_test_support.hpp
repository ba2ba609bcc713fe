// Shared helpers of the 3-D solver tests: the benchmark instance paths and checks every solver
// result must pass (valid assignment, recomputed cost = objective), plus a brute-force optimum.
//
// TEMPORARY: read_instance_local / read_optima_local are a minimal reader of the DESIGN §3 text
// format, used only until io/instance_text.cpp (branch io) lands on main; then they are replaced by
// read_3dap_instance / read_known_optima.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/assignment_types.hpp"

namespace trackassoc::testing_support {

inline std::string bench_dir() { return std::string(TRACKASSOC_SHARED_DIR) + "/benchmarks/3dap"; }
inline std::string decomplib(const std::string& name) { return bench_dir() + "/decomplib/" + name; }
inline std::string balas_saltzman(const std::string& name) { return bench_dir() + "/balas-saltzman/" + name; }

inline CostTensor3 read_instance_local(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  int s = 0, n1 = 0, n2 = 0, n3 = 0;
  in >> s >> n1 >> n2 >> n3;
  if (!in || s != 3) throw std::runtime_error("bad header in " + path);
  CostTensor3 b(n1, n2, n3);
  for (auto& x : b.cost)
    if (!(in >> x)) throw std::runtime_error("too few costs in " + path);
  return b;
}

inline std::map<std::string, double> read_optima_local(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, double> m;
  std::string name;
  double v;
  while (in >> name >> v) m[name] = v;
  return m;
}

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

}  // namespace trackassoc::testing_support
