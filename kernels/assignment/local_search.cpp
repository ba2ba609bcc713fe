#include "kernels/assignment/local_search.hpp"

#include <chrono>
#include <cmath>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void LocalSearchOptions::validate() const {
  require(max_rounds >= 1, "LocalSearchOptions.max_rounds",
          "must be >= 1, got " + std::to_string(max_rounds));
}

namespace {

// Re-solves dimension `free_dim` with the other two fixed. Returns true if the cost decreased.
bool reassign_dimension(const CostTensor3& b, std::vector<Tuple3>& tuples, int free_dim,
                        std::vector<double>& matrix) {
  const int32_t m = static_cast<int32_t>(tuples.size());
  const int32_t n = free_dim == 0 ? b.n1 : (free_dim == 1 ? b.n2 : b.n3);
  matrix.resize(static_cast<std::size_t>(m) * n);
  double current = 0.0;
  for (int32_t r = 0; r < m; ++r) {
    Tuple3 t = tuples[r];
    current += b.at(t[0], t[1], t[2]);
    double* row = matrix.data() + static_cast<std::size_t>(r) * n;
    for (int32_t x = 0; x < n; ++x) {
      t[free_dim] = x;
      row[x] = b.at(t[0], t[1], t[2]);
    }
  }
  const LapResult lap = solve_lap(matrix, m, n);
  if (!lap.feasible) return false;
  // Accept only a strict improvement beyond rounding, so the search cannot cycle.
  if (!(lap.cost < current - 1e-12 * std::max(1.0, std::abs(current)))) return false;
  for (int32_t r = 0; r < m; ++r) tuples[r][free_dim] = lap.row_to_col[r];
  return true;
}

}  // namespace

LocalSearchStats polish_canonical(const CostTensor3& b, std::vector<Tuple3>& tuples,
                                  const LocalSearchOptions& options) {
  if (tuples.empty()) return {0, true};
  std::vector<double> matrix;
  int rounds = 0;
  int since_improvement = 0;  // consecutive moves without improvement
  int dim = 2;
  while (rounds < options.max_rounds) {
    ++rounds;
    for (int move = 0; move < 3; ++move) {
      if (reassign_dimension(b, tuples, dim, matrix))
        since_improvement = 0;
      else
        ++since_improvement;
      dim = (dim + 1) % 3;
      if (since_improvement >= 3) return {rounds, true};  // three moves failed in a row: local optimum
    }
  }
  return {rounds, false};
}

std::vector<Tuple3> to_canonical(const CanonicalProblem3& p, const std::vector<Tuple3>& original) {
  const CostTensor3& t = p.tensor;
  const std::array<int32_t, 3> n{t.n1, t.n2, t.n3};
  std::array<std::vector<char>, 3> used;
  for (int d = 0; d < 3; ++d) used[d].assign(n[d], 0);
  // Next free dummy per canonical dimension (padded: dummies are the indices ≥ original size).
  std::array<int32_t, 3> next_dummy{};
  for (int d = 0; d < 3; ++d) next_dummy[d] = p.padded ? p.original_n[p.original_dim[d]] : n[d];
  std::vector<Tuple3> out;
  out.reserve(t.n1);
  for (const Tuple3& o : original) {
    Tuple3 c{};
    bool ok = true;
    for (int d = 0; d < 3; ++d) {
      const int32_t x = o[p.original_dim[d]];
      if (x == kNoTrack && p.padded) {
        if (next_dummy[d] >= n[d]) ok = false;
        c[d] = next_dummy[d]++;
      } else if (x < 0 || x >= n[d] || used[d][x]) {
        ok = false;
      } else {
        c[d] = x;
      }
    }
    if (!ok || static_cast<int32_t>(out.size()) >= t.n1) continue;  // invalid tuple: dropped, refilled below
    for (int d = 0; d < 3; ++d) used[d][c[d]] = 1;
    out.push_back(c);
  }
  // Complete: every canonical i must be used; pair it with the first free j and k.
  std::array<int32_t, 3> cursor{0, 0, 0};
  auto next_free = [&](int d) {
    while (used[d][cursor[d]]) ++cursor[d];
    used[d][cursor[d]] = 1;
    return cursor[d];
  };
  while (static_cast<int32_t>(out.size()) < t.n1) out.push_back({next_free(0), next_free(1), next_free(2)});
  return out;
}

Solution3 solve_local_search3(const CostTensor3& cost, const std::vector<Tuple3>& start,
                              const LocalSearchOptions& options) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const CanonicalProblem3 p = make_canonical(cost);
  std::vector<Tuple3> tuples = to_canonical(p, start);
  const LocalSearchStats stats = polish_canonical(p.tensor, tuples, options);
  Solution3 s;
  s.tuples = to_original(p, tuples);
  s.summary.sweeps = stats.rounds;
  s.summary.iterations = stats.rounds;
  s.summary.termination = stats.converged ? Termination::kConverged : Termination::kIterationLimit;
  finish_summary(cost, s.tuples, std::numeric_limits<double>::quiet_NaN(), s.summary);
  s.summary.wall_time_s = seconds_since(t0);
  return s;
}

}  // namespace trackassoc
