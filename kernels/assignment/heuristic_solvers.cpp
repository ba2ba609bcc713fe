// Greedy and sequential pairwise heuristics for the 3-D assignment (docs/design.md §4.5). See the header.
//
// Unequal sizes and misses (what is supported):
// * miss_cost = +inf (the pipeline's default): both solvers return min(n1, n2, n3) complete
//   tuples, or report Termination::kInfeasible when +inf entries (forbidden tuples) leave them
//   short.
// * finite miss_cost m ≥ 0: the solvers return complete tuples only. An index in no tuple counts as
//   a tuple of its own, 2m (assignment_types.hpp, the same for every solver), so greedy takes a
//   complete tuple only when b_ijk < 6m (the three singletons it replaces); indices in no tuple are
//   simply not listed (the pipeline turns them into one-track tuples). summary.objective =
//   assignment_cost(), as for every solver. Partial tuples (i, j, –) are never produced: the dense
//   tensor has no cost for a pair without its third index.
// Ties are broken by the linear index (i·n2 + j)·n3 + k, so the result is deterministic.
#include "kernels/assignment/heuristic_solvers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

void check_tensor(const CostTensor3& b, const char* solver) {
  require(
      b.n1 >= 0 && b.n2 >= 0 && b.n3 >= 0 && b.cost.size() == static_cast<std::size_t>(b.n1) * b.n2 * b.n3,
      solver, "cost tensor size does not match n1*n2*n3");
  require(!std::isnan(b.miss_cost) && b.miss_cost >= 0.f, std::string(solver) + ".miss_cost",
          "must be >= 0 or +inf, got " + std::to_string(b.miss_cost));
  for (std::size_t p = 0; p < b.cost.size(); ++p)
    if (std::isnan(b.cost[p]) || b.cost[p] == -std::numeric_limits<float>::infinity())
      throw InputError(std::string(solver) + ": cost tensor entry " + std::to_string(p) +
                       " is NaN or -inf; costs must be finite or +inf (forbidden)");
}

// Fills the summary common to both heuristics.
void finish(const CostTensor3& b, Solution3& sol, std::chrono::steady_clock::time_point t0) {
  std::sort(sol.tuples.begin(), sol.tuples.end());
  SolverSummary& s = sol.summary;
  s.objective = assignment_cost(b, sol.tuples);
  const int32_t m = std::min({b.n1, b.n2, b.n3});
  const bool complete = static_cast<int32_t>(sol.tuples.size()) == m;
  s.feasible = is_valid_assignment(b, sol.tuples) && (std::isfinite(b.miss_cost) || complete);
  s.termination = s.feasible ? Termination::kHeuristic : Termination::kInfeasible;
  s.iterations = 1;
  if (std::isfinite(b.miss_cost)) {
    const int64_t unassigned = int64_t{b.n1} + b.n2 + b.n3 - 3 * static_cast<int64_t>(sol.tuples.size());
    s.message = std::to_string(sol.tuples.size()) + " tuples, " + std::to_string(unassigned) +
                " indices alone (2·miss_cost each in the objective)";
  } else if (!complete) {
    s.message = "only " + std::to_string(sol.tuples.size()) + " of " + std::to_string(m) +
                " tuples have a finite cost";
  }
  s.wall_time_s = seconds_since(t0);
}

struct Candidate {
  float cost;
  uint32_t index;  // linear index into the tensor
  bool operator<(const Candidate& o) const { return cost < o.cost || (cost == o.cost && index < o.index); }
};

}  // namespace

// Greedy in rounds: take the B cheapest live candidates (nth_element + sort), assign those whose
// indices are free in order, then drop every candidate that touches an assigned index. The taken
// candidates are exactly the cheapest of the live set, so this is the textbook greedy, but only
// the head of the order is ever sorted; after t assignments only ~((n−t)/n)³ of the candidates
// are still live, so the rounds shrink fast.
Solution3 solve_greedy3(const CostTensor3& b, const GreedyOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  options.validate();
  check_tensor(b, "solve_greedy3");
  require(
      b.size() < (std::size_t{1} << 32), "solve_greedy3",
      "tensor of " + std::to_string(b.size()) + " entries is too large for the dense greedy (limit 2^32)");
  Solution3 sol;
  const int32_t m = std::min({b.n1, b.n2, b.n3});
  // With a finite miss cost, a tuple is only worth taking below the three singletons it replaces.
  const double take_below =
      std::isfinite(b.miss_cost) ? 6.0 * b.miss_cost : std::numeric_limits<double>::infinity();
  std::vector<Candidate> live;
  live.reserve(b.size());
  for (std::size_t p = 0; p < b.size(); ++p)
    if (std::isfinite(b.cost[p]) && b.cost[p] < take_below)
      live.push_back({b.cost[p], static_cast<uint32_t>(p)});

  std::vector<char> used1(b.n1, 0), used2(b.n2, 0), used3(b.n3, 0);
  const std::size_t n23 = static_cast<std::size_t>(b.n2) * b.n3;
  auto decode = [&](uint32_t p) {
    return Tuple3{static_cast<int32_t>(p / n23), static_cast<int32_t>(p % n23 / b.n3),
                  static_cast<int32_t>(p % b.n3)};
  };
  auto is_free = [&](const Tuple3& t) { return !used1[t[0]] && !used2[t[1]] && !used3[t[2]]; };
  int64_t rounds = 0;
  while (!live.empty() && static_cast<int32_t>(sol.tuples.size()) < m) {
    ++rounds;
    const std::size_t remaining = static_cast<std::size_t>(m) - sol.tuples.size();
    const std::size_t head = std::min(live.size(), std::max<std::size_t>(4 * remaining, 1024));
    std::nth_element(live.begin(), live.begin() + (head - 1), live.end());
    std::sort(live.begin(), live.begin() + head);
    for (std::size_t q = 0; q < head && static_cast<int32_t>(sol.tuples.size()) < m; ++q) {
      const Tuple3 t = decode(live[q].index);
      if (!is_free(t)) continue;
      used1[t[0]] = used2[t[1]] = used3[t[2]] = 1;
      sol.tuples.push_back(t);
    }
    std::erase_if(live, [&](const Candidate& c) { return !is_free(decode(c.index)); });
  }
  finish(b, sol, t0);
  sol.summary.iterations = rounds;
  return sol;
}

// Sequential pairwise: LAP on c12(i, j) = min_k b_ijk, then LAP of the merged pairs against
// sensor 3 with cost b_ijk. With a finite miss cost m both LAPs allow unassigned rows/columns at
// 1.5·m each, so that a pair or a tuple is kept exactly when it beats the misses it saves (3·m).
Solution3 solve_pairwise3(const CostTensor3& b, const PairwiseOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  options.validate();
  check_tensor(b, "solve_pairwise3");
  Solution3 sol;
  const int32_t n1 = b.n1, n2 = b.n2, n3 = b.n3;
  LapOptions lap;
  if (std::isfinite(b.miss_cost)) {
    lap.allow_unassigned = true;
    lap.unassigned_cost = 1.5 * static_cast<double>(b.miss_cost);
  }
  if (std::min({n1, n2, n3}) > 0) {
    // Stage 1: sensors 1 and 2, each pair at its best third index.
    std::vector<double> c12(static_cast<std::size_t>(n1) * n2);
    for (int32_t i = 0; i < n1; ++i)
      for (int32_t j = 0; j < n2; ++j) {
        const float* row = &b.cost[b.index(i, j, 0)];
        c12[static_cast<std::size_t>(i) * n2 + j] = *std::min_element(row, row + n3);
      }
    const LapResult first = solve_lap(c12, n1, n2, lap);
    std::vector<std::pair<int32_t, int32_t>> pairs;
    for (int32_t i = 0; i < n1; ++i)
      if (first.row_to_col[i] >= 0 &&
          std::isfinite(c12[static_cast<std::size_t>(i) * n2 + first.row_to_col[i]]))
        pairs.emplace_back(i, first.row_to_col[i]);
    // Stage 2: the merged pairs against sensor 3.
    const int32_t np = static_cast<int32_t>(pairs.size());
    std::vector<double> c3(static_cast<std::size_t>(np) * n3);
    for (int32_t p = 0; p < np; ++p)
      for (int32_t k = 0; k < n3; ++k)
        c3[static_cast<std::size_t>(p) * n3 + k] = b.at(pairs[p].first, pairs[p].second, k);
    if (np > 0) {
      const LapResult second = solve_lap(c3, np, n3, lap);
      for (int32_t p = 0; p < np; ++p) {
        const int32_t k = second.row_to_col[p];
        if (k >= 0 && std::isfinite(c3[static_cast<std::size_t>(p) * n3 + k]))
          sol.tuples.push_back({pairs[p].first, pairs[p].second, k});
      }
    }
  }
  finish(b, sol, t0);
  sol.summary.iterations = 2;
  return sol;
}

}  // namespace trackassoc
