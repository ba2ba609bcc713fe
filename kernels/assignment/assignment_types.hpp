// Shared types of the 3-D (and S-D) assignment stage: the dense cost tensor, the solution and the
// solver summary (docs/design.md §2 "Options in, summary out", after Ceres' Solver::Summary).
//
// 3-D assignment problem (seed 000 Eq. 5–6): choose tuples (i, j, k), one index per sensor, each
// index used at most once per dimension, minimising Σ b_ijk. With n1 = n2 = n3 = n every index is
// used exactly once (an axial 3-D assignment, NP-hard: Karp 1972). Unequal sizes are handled by
// tuples that leave a dimension out, index kNoTrack (the "dummy index 0" of the S-D assignment
// literature, docs/design.md §4.3), at CostTensor3::miss_cost per missing index.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace trackassoc {

inline constexpr int32_t kNoTrack = -1;

// Dense n1×n2×n3 cost tensor, float (docs/design.md §2 Precision), first index slowest:
//   b(i, j, k) = cost[(i·n2 + j)·n3 + k].
struct CostTensor3 {
  int32_t n1 = 0, n2 = 0, n3 = 0;
  std::vector<float> cost;
  // Cost of leaving one index of a tuple unassigned (dummy). +inf: every tuple must be complete,
  // and a solver assigns min(n1, n2, n3) complete tuples.
  float miss_cost = std::numeric_limits<float>::infinity();

  CostTensor3() = default;
  CostTensor3(int32_t a, int32_t b, int32_t c, float fill = 0.f)
      : n1(a), n2(b), n3(c), cost(static_cast<std::size_t>(a) * b * c, fill) {}
  std::size_t size() const { return cost.size(); }
  std::size_t index(int32_t i, int32_t j, int32_t k) const {
    return (static_cast<std::size_t>(i) * n2 + j) * n3 + k;
  }
  float at(int32_t i, int32_t j, int32_t k) const { return cost[index(i, j, k)]; }
  float& at(int32_t i, int32_t j, int32_t k) { return cost[index(i, j, k)]; }
};

using Tuple3 = std::array<int32_t, 3>;

// Why a solver stopped.
enum class Termination {
  kOptimal,       // proven optimal (exact solver, or a zero gap)
  kConverged,     // a fixed point / no improving move (Hopfield, local search)
  kGapTolerance,  // relative duality gap below the tolerance (Lagrangian relaxation)
  kIterationLimit,
  kTimeLimit,
  kCycle,       // synchronous network entered a 2-cycle
  kInfeasible,  // no feasible assignment exists or none was found
  kHeuristic,   // a one-pass heuristic (greedy, pairwise) finished
};

inline const char* termination_name(Termination t) {
  switch (t) {
    case Termination::kOptimal:
      return "optimal";
    case Termination::kConverged:
      return "converged";
    case Termination::kGapTolerance:
      return "gap_tolerance";
    case Termination::kIterationLimit:
      return "iteration_limit";
    case Termination::kTimeLimit:
      return "time_limit";
    case Termination::kCycle:
      return "cycle";
    case Termination::kInfeasible:
      return "infeasible";
    case Termination::kHeuristic:
      return "heuristic";
  }
  return "unknown";
}

struct SolverSummary {
  Termination termination = Termination::kHeuristic;
  bool feasible = false;
  double objective = std::numeric_limits<double>::quiet_NaN();    // cost of the returned tuples
  double lower_bound = std::numeric_limits<double>::quiet_NaN();  // a valid bound, where defined
  double gap = std::numeric_limits<double>::quiet_NaN();  // (objective − bound) / max(|objective|, 1e-9)
  double abs_gap = std::numeric_limits<double>::quiet_NaN();  // objective − bound
  int64_t iterations = 0;
  int64_t sweeps = 0;
  double wall_time_s = 0.0;
  std::string message;
};

// Optional per-restart table of multi-start solvers (Hopfield: one row per restart, docs/design.md §4.4
// "Report per restart"), written to /associations/<name>/restarts/ (one 1-D dataset per column);
// empty when the solver has no restarts. All columns have size() rows.
struct RestartTable {
  std::vector<int32_t> restart;           // restart number (its random stream)
  std::vector<int32_t> valid_raw;         // 1: the network's own state was a valid assignment (before repair)
  std::vector<int32_t> sweeps;            // discrete sweeps or continuous steps to convergence (or the limit)
  std::vector<int32_t> mean_field_steps;  // continuous steps of a mean-field start (0 without one)
  std::vector<double> energy;             // final network energy (normalised-cost units)
  std::vector<double> repaired_objective;  // cost of the repaired assignment (before any polish)
  std::vector<double> objective;           // cost of the restart's final assignment
  std::size_t size() const { return restart.size(); }
  bool consistent() const {
    const std::size_t n = restart.size();
    return valid_raw.size() == n && sweeps.size() == n && mean_field_steps.size() == n &&
           energy.size() == n && repaired_objective.size() == n && objective.size() == n;
  }
  bool operator==(const RestartTable&) const = default;
};

struct Solution3 {
  std::vector<Tuple3> tuples;
  SolverSummary summary;
  // Optional energy trace of iterative solvers (Hopfield: restarts × sweeps, row-major, NaN-padded),
  // written to /associations/<name>/energy; empty when not recorded.
  int32_t energy_rows = 0, energy_cols = 0;
  std::vector<float> energy_trace;
  RestartTable restarts;  // optional, see RestartTable
};

// Fills lower_bound, abs_gap and gap from summary.objective and a bound (NaN gaps when the bound is
// NaN or the result infeasible). Shared by the 3-D and S-D solvers.
inline void set_bound_and_gap(SolverSummary& summary, double lower_bound) {
  summary.lower_bound = lower_bound;
  if (std::isnan(lower_bound) || !summary.feasible) {
    summary.abs_gap = summary.gap = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  summary.abs_gap = std::max(0.0, summary.objective - lower_bound);
  summary.gap = summary.abs_gap / std::max(std::abs(summary.objective), 1e-9);
}

// Σ over tuples of b_ijk, with miss_cost per kNoTrack index. With a finite miss_cost every index
// belongs to some tuple: an index in none counts as a tuple of its own, 2·miss_cost (so leaving an
// index out is never cheaper than saying so). Double accumulation.
inline double assignment_cost(const CostTensor3& b, const std::vector<Tuple3>& tuples) {
  double sum = 0.0;
  int64_t covered = 0;
  for (const auto& t : tuples) {
    const int missing = (t[0] < 0) + (t[1] < 0) + (t[2] < 0);
    covered += 3 - missing;
    if (missing == 0)
      sum += b.at(t[0], t[1], t[2]);
    else
      sum += static_cast<double>(b.miss_cost) * missing;
  }
  if (std::isfinite(b.miss_cost)) {
    const int64_t uncovered = static_cast<int64_t>(b.n1) + b.n2 + b.n3 - covered;
    sum += 2.0 * static_cast<double>(b.miss_cost) * static_cast<double>(uncovered);
  }
  return sum;
}

// True when every index is in range and used at most once per dimension, and, when miss_cost is
// infinite, every tuple is complete and there are min(n1, n2, n3) of them.
inline bool is_valid_assignment(const CostTensor3& b, const std::vector<Tuple3>& tuples) {
  const std::array<int32_t, 3> n{b.n1, b.n2, b.n3};
  std::array<std::vector<char>, 3> used;
  for (int d = 0; d < 3; ++d) used[d].assign(n[d], 0);
  for (const auto& t : tuples) {
    for (int d = 0; d < 3; ++d) {
      if (t[d] == kNoTrack) {
        if (std::isinf(b.miss_cost)) return false;
        continue;
      }
      if (t[d] < 0 || t[d] >= n[d] || used[d][t[d]]) return false;
      used[d][t[d]] = 1;
    }
  }
  if (std::isinf(b.miss_cost)) {
    const int32_t m = std::min({b.n1, b.n2, b.n3});
    return static_cast<int32_t>(tuples.size()) == m;
  }
  return true;
}

}  // namespace trackassoc
