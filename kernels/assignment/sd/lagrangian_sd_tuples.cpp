#include "kernels/assignment/sd/lagrangian_sd_tuples.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "kernels/assignment/lagrangian_subgradient.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The tuples grouped by their indices on the kept sensors a and b: one group per (i, j) pair of
// real indices (an edge of the LAP), per i with j the dummy (row), per j with i the dummy (column),
// and the tuples with both dummies (free in the relaxed problem).
struct KeptPairGroups {
  std::vector<int32_t> edge_row, edge_col;    // per edge group
  std::vector<int64_t> edge_start;            // edges + 1 offsets into `order`
  std::vector<int64_t> row_start, col_start;  // n_a + 1, n_b + 1 offsets into `order`
  std::vector<int64_t> free_start;            // 2 offsets: the free tuples
  std::vector<int32_t> order;                 // tuple ids, grouped as above
  std::vector<int32_t> edge_csr_start;        // n_a + 1: the edges of row i, by column
};

KeptPairGroups group_by_kept_pair(const TupleListSD& p, int32_t a, int32_t b) {
  const int32_t S = p.dims();
  const auto T = static_cast<int32_t>(p.size());
  const int32_t na = p.n[a], nb = p.n[b];
  // Sort key: edges (i, j) first, by i then j; then rows; then columns; then free tuples.
  auto key = [&](int32_t t) -> std::pair<int64_t, int64_t> {
    const int32_t i = p.tuples[static_cast<std::size_t>(t) * S + a];
    const int32_t j = p.tuples[static_cast<std::size_t>(t) * S + b];
    if (i >= 0 && j >= 0) return {0, static_cast<int64_t>(i) * nb + j};
    if (i >= 0) return {1, i};
    if (j >= 0) return {2, j};
    return {3, 0};
  };
  KeptPairGroups g;
  g.order.resize(T);
  std::iota(g.order.begin(), g.order.end(), 0);
  std::stable_sort(g.order.begin(), g.order.end(), [&](int32_t x, int32_t y) { return key(x) < key(y); });
  g.row_start.assign(static_cast<std::size_t>(na) + 1, 0);
  g.col_start.assign(static_cast<std::size_t>(nb) + 1, 0);
  g.edge_csr_start.assign(static_cast<std::size_t>(na) + 1, 0);
  int64_t pos = 0;
  for (; pos < T && key(g.order[pos]).first == 0; ++pos) {
    const auto k = key(g.order[pos]).second;
    if (pos == 0 || key(g.order[pos - 1]).second != k) {
      g.edge_start.push_back(pos);
      g.edge_row.push_back(static_cast<int32_t>(k / nb));
      g.edge_col.push_back(static_cast<int32_t>(k % nb));
      ++g.edge_csr_start[k / nb + 1];
    }
  }
  g.edge_start.push_back(pos);
  for (int32_t i = 0; i < na; ++i) g.edge_csr_start[i + 1] += g.edge_csr_start[i];
  for (; pos < T && key(g.order[pos]).first == 1; ++pos) ++g.row_start[key(g.order[pos]).second + 1];
  for (; pos < T && key(g.order[pos]).first == 2; ++pos) ++g.col_start[key(g.order[pos]).second + 1];
  const int64_t rows_begin = g.edge_start.back();
  for (int32_t i = 0; i < na; ++i) g.row_start[i + 1] += g.row_start[i];
  for (auto& x : g.row_start) x += rows_begin;
  for (int32_t j = 0; j < nb; ++j) g.col_start[j + 1] += g.col_start[j];
  for (auto& x : g.col_start) x += g.row_start.back();
  g.free_start = {g.col_start.back(), T};
  return g;
}

}  // namespace

void TupleListSD::validate() const {
  const int32_t S = dims();
  require(S >= 2, "TupleListSD.n", "expected at least 2 sensors, found " + std::to_string(S));
  for (int32_t s = 0; s < S; ++s)
    require(n[s] >= 0, "TupleListSD.n", "sensor " + std::to_string(s) + " has a negative count");
  require(tuples.size() == cost.size() * static_cast<std::size_t>(S), "TupleListSD.tuples",
          "expected " + std::to_string(cost.size()) + " × " + std::to_string(S) + " indices, found " +
              std::to_string(tuples.size()));
  std::vector<std::vector<uint8_t>> singleton(S);
  for (int32_t s = 0; s < S; ++s) singleton[s].assign(n[s], 0);
  for (std::size_t t = 0; t < size(); ++t) {
    require(std::isfinite(cost[t]), "TupleListSD.cost",
            "tuple " + std::to_string(t) + " has a non-finite cost");
    int32_t real = 0, last = -1;
    for (int32_t s = 0; s < S; ++s) {
      const int32_t i = tuples[t * S + s];
      require(i == kNoTrack || (i >= 0 && i < n[s]), "TupleListSD.tuples",
              "tuple " + std::to_string(t) + " has index " + std::to_string(i) + " on sensor " +
                  std::to_string(s) + " (expected " + std::to_string(kNoTrack) + " or 0.." +
                  std::to_string(n[s] - 1) + ")");
      if (i >= 0) ++real, last = s;
    }
    require(real > 0, "TupleListSD.tuples", "tuple " + std::to_string(t) + " is all dummies");
    if (real == 1) singleton[last][tuples[t * S + last]] = 1;
  }
  for (int32_t s = 0; s < S; ++s)
    for (int32_t i = 0; i < n[s]; ++i)
      require(singleton[s][i], "TupleListSD.tuples",
              "index " + std::to_string(i) + " of sensor " + std::to_string(s) + " has no singleton tuple");
}

SolutionSD solve_lagrangian_sd_tuples(const TupleListSD& p, const LagrangianOptions& options) {
  options.validate();
  p.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const int32_t S = p.dims();
  const auto T = static_cast<int32_t>(p.size());
  // Kept sensors: the two with most tracks (the relaxation is tightest where most is kept).
  std::vector<int32_t> by_size(S);
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](int32_t x, int32_t y) { return p.n[x] > p.n[y]; });
  const int32_t a = std::min(by_size[0], by_size[1]), b = std::max(by_size[0], by_size[1]);
  const int32_t na = p.n[a], nb = p.n[b];
  const KeptPairGroups g = group_by_kept_pair(p, a, b);

  // Flat μ over the relaxed sensors, sensor by sensor; offset[s] (−1 for a and b).
  std::vector<int64_t> offset(S, -1);
  std::size_t flat = 0;
  for (int32_t s = 0; s < S; ++s)
    if (s != a && s != b) offset[s] = static_cast<int64_t>(flat), flat += p.n[s];
  // Each tuple's singleton sum (for the recovery's "better than its singletons" test).
  std::vector<std::vector<double>> single(S);
  for (int32_t s = 0; s < S; ++s) single[s].assign(p.n[s], 0.0);
  for (int32_t t = 0; t < T; ++t) {
    int32_t real = 0, last = 0;
    for (int32_t s = 0; s < S; ++s)
      if (p.tuples[static_cast<std::size_t>(t) * S + s] >= 0) ++real, last = s;
    if (real == 1) single[last][p.tuples[static_cast<std::size_t>(t) * S + last]] = p.cost[t];
  }
  std::vector<double> singles_of(T, 0.0);
  for (int32_t t = 0; t < T; ++t)
    for (int32_t s = 0; s < S; ++s)
      if (const int32_t i = p.tuples[static_cast<std::size_t>(t) * S + s]; i >= 0)
        singles_of[t] += single[s][i];

  std::vector<double> reduced(T);
  std::vector<int32_t> relaxed;  // the relaxed solution's tuples
  auto group_min = [&](int64_t lo, int64_t hi, int32_t& arg) {
    double best = kInf;
    for (int64_t q = lo; q < hi; ++q)
      if (reduced[g.order[q]] < best) best = reduced[g.order[q]], arg = g.order[q];
    return best;
  };
  std::vector<double> r(na), q(nb), e_cost;
  std::vector<int32_t> r_arg(na), q_arg(nb), e_arg(g.edge_row.size()), e_col;
  std::vector<int32_t> e_start(static_cast<std::size_t>(na) + 1);

  SubgradientProblem problem;
  problem.zero_subgradient_is_optimal = true;  // the relaxed constraints are equalities
  problem.dual = [&](const std::vector<double>& mu, double& bound, std::vector<double>& grad) {
    for (int32_t t = 0; t < T; ++t) {
      double v = p.cost[t];
      for (int32_t s = 0; s < S; ++s)
        if (const int32_t i = p.tuples[static_cast<std::size_t>(t) * S + s]; i >= 0 && offset[s] >= 0)
          v -= mu[offset[s] + i];
      reduced[t] = v;
    }
    double constant = 0.0;
    for (int32_t i = 0; i < na; ++i)
      constant += r[i] = group_min(g.row_start[i], g.row_start[i + 1], r_arg[i]);
    for (int32_t j = 0; j < nb; ++j)
      constant += q[j] = group_min(g.col_start[j], g.col_start[j + 1], q_arg[j]);
    // The LAP keeps the edges that beat leaving both ends unmatched (d − r − q < 0).
    e_col.clear();
    e_cost.clear();
    std::vector<int32_t> e_id;
    std::fill(e_start.begin(), e_start.end(), 0);
    for (std::size_t e = 0; e < g.edge_row.size(); ++e) {
      const int32_t i = g.edge_row[e], j = g.edge_col[e];
      const double d = group_min(g.edge_start[e], g.edge_start[e + 1], e_arg[e]) - r[i] - q[j];
      if (d < 0.0) {
        e_col.push_back(j);
        e_cost.push_back(d);
        e_id.push_back(static_cast<int32_t>(e));
        ++e_start[i + 1];
      }
    }
    for (int32_t i = 0; i < na; ++i) e_start[i + 1] += e_start[i];
    SparseCostView view{na, nb, e_start, e_col, e_cost};
    LapOptions lap_options;
    lap_options.allow_unassigned = true;
    lap_options.unassigned_cost = 0.0;
    const LapResult lap = solve_gated_lap(view, lap_options);
    if (!lap.feasible) return false;
    double free_sum = 0.0, mu_sum = 0.0;
    relaxed.clear();
    for (int64_t k = g.free_start[0]; k < g.free_start[1]; ++k)
      if (reduced[g.order[k]] < 0.0) free_sum += reduced[g.order[k]], relaxed.push_back(g.order[k]);
    for (double m : mu) mu_sum += m;
    bound = constant + lap.cost + free_sum + mu_sum;
    for (int32_t i = 0; i < na; ++i) {
      int32_t t = r_arg[i];
      if (const int32_t j = lap.row_to_col[i]; j >= 0)
        for (int32_t k = e_start[i]; k < e_start[i + 1]; ++k)
          if (e_col[k] == j) t = e_arg[e_id[k]];
      relaxed.push_back(t);
    }
    for (int32_t j = 0; j < nb; ++j)
      if (lap.col_to_row[j] < 0) relaxed.push_back(q_arg[j]);
    std::fill(grad.begin(), grad.end(), 1.0);
    for (int32_t t : relaxed)
      for (int32_t s = 0; s < S; ++s)
        if (const int32_t i = p.tuples[static_cast<std::size_t>(t) * S + s]; i >= 0 && offset[s] >= 0)
          grad[offset[s] + i] -= 1.0;
    return true;
  };

  // Recovery: the relaxed tuples, then all, by ascending reduced cost; see the header.
  std::vector<int32_t> best, order(T), chosen;
  std::vector<std::vector<uint8_t>> taken(S);
  problem.primal = [&](const std::vector<double>&, double incumbent) {
    for (int32_t s = 0; s < S; ++s) taken[s].assign(p.n[s], 0);
    chosen.clear();
    double total = 0.0;
    auto take = [&](int32_t t) {
      const int32_t* x = &p.tuples[static_cast<std::size_t>(t) * S];
      for (int32_t s = 0; s < S; ++s)
        if (x[s] >= 0 && taken[s][x[s]]) return;
      if (!(p.cost[t] < singles_of[t]) && std::count_if(x, x + S, [](int32_t i) { return i >= 0; }) > 1)
        return;
      for (int32_t s = 0; s < S; ++s)
        if (x[s] >= 0) taken[s][x[s]] = 1;
      chosen.push_back(t);
      total += p.cost[t];
    };
    auto by_reduced = [&](int32_t x, int32_t y) {
      return reduced[x] < reduced[y] || (reduced[x] == reduced[y] && x < y);
    };
    std::sort(relaxed.begin(), relaxed.end(), by_reduced);
    for (int32_t t : relaxed) take(t);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), by_reduced);
    for (int32_t t : order) take(t);  // ends with every index taken: the singletons are listed
    if (!(total < incumbent)) return incumbent;
    best = chosen;
    return total;
  };
  const SubgradientResult run = run_subgradient(problem, std::vector<double>(flat, 0.0), options, t0);

  SolutionSD sol;
  sol.S = S;
  std::sort(best.begin(), best.end());
  for (int32_t t : best)
    sol.tuples.insert(sol.tuples.end(), p.tuples.begin() + static_cast<std::ptrdiff_t>(t) * S,
                      p.tuples.begin() + static_cast<std::ptrdiff_t>(t + 1) * S);
  sol.summary.feasible = !best.empty() || T == 0;
  sol.summary.objective = 0.0;
  for (int32_t t : best) sol.summary.objective += p.cost[t];
  set_bound_and_gap(sol.summary, std::isfinite(run.lower_bound) ? run.lower_bound
                                                                : std::numeric_limits<double>::quiet_NaN());
  sol.summary.iterations = run.iterations;
  sol.summary.termination = sol.summary.feasible ? run.termination : Termination::kInfeasible;
  sol.summary.message = std::string("S-D relaxation over ") + std::to_string(T) +
                        " listed tuples, step rule " + enum_name(options.step_rule);
  sol.summary.wall_time_s = seconds_since(t0);
  return sol;
}

}  // namespace trackassoc
