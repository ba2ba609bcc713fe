#include "kernels/assignment/sd/lagrangian_sd.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "kernels/assignment/lagrangian_subgradient.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Σ_{q ≥ from} μ_q(i_q) for every combination of the sensors from … S−1 (a block of length
// stride[from−1], or the whole tensor's tail), dummy μ = 0.
void tail_penalty(const CostTensorSD& c, const std::vector<std::vector<double>>& mu, int32_t from,
                  std::vector<double>& p) {
  const int32_t S = c.dims();
  const std::size_t len = from == 0 ? c.cost.size() : c.stride[from - 1];
  p.assign(len, 0.0);
  for (int32_t q = from; q < S; ++q) {
    const std::size_t st = c.stride[q], extent = static_cast<std::size_t>(c.n[q]) + 1;
    for (std::size_t r = 0; r < len; ++r) p[r] += mu[q][(r / st) % extent];
  }
}

// min over a block of (cost − penalty), and its position.
inline double block_min(const float* cost, const double* p, std::size_t len, std::size_t& arg) {
  double best = kInf;
  arg = 0;
  for (std::size_t r = 0; r < len; ++r) {
    const double v = static_cast<double>(cost[r]) - p[r];
    if (v < best) {
      best = v;
      arg = r;
    }
  }
  return best;
}

// Writes the indices of sensors from … S−1 encoded by block position r into t.
void decode_tail(const CostTensorSD& c, int32_t from, std::size_t r, int32_t* t) {
  for (int32_t q = from; q < c.dims(); ++q) {
    const int32_t i = static_cast<int32_t>((r / c.stride[q]) % (static_cast<std::size_t>(c.n[q]) + 1));
    t[q] = i == c.n[q] ? kNoTrack : i;
  }
}

// Feasible recovery: the (i_1, i_2) pairs, then sensors 3 … S one at a time (see the header).
std::vector<int32_t> recover(const CostTensorSD& c, const std::vector<std::vector<double>>& mu,
                             std::vector<int32_t> partial) {
  const int32_t S = c.dims();
  std::vector<double> p, e, e_new;
  std::vector<int32_t> t(S);
  for (int32_t s = 2; s < S; ++s) {
    tail_penalty(c, mu, s + 1, p);
    const std::size_t len = c.stride[s];
    const int32_t m = static_cast<int32_t>(partial.size() / S), ns = c.n[s];
    auto block = [&](const int32_t* prefix, int32_t i) {
      std::size_t off = static_cast<std::size_t>(i) * c.stride[s];
      for (int32_t q = 0; q < s; ++q)
        off += static_cast<std::size_t>(prefix[q] < 0 ? c.n[q] : prefix[q]) * c.stride[q];
      std::size_t arg;
      return block_min(c.cost.data() + off, p.data(), len, arg);
    };
    e.assign(static_cast<std::size_t>(m) * (ns + 1), 0.0);
    parallel_for_range(static_cast<std::size_t>(m), 4, [&](std::size_t b, std::size_t end) {
      for (std::size_t r = b; r < end; ++r)
        for (int32_t i = 0; i <= ns; ++i) e[r * (ns + 1) + i] = block(partial.data() + r * S, i);
    });
    e_new.assign(ns, 0.0);
    std::fill(t.begin(), t.end(), kNoTrack);
    for (int32_t i = 0; i < ns; ++i) e_new[i] = block(t.data(), i);
    const DimensionMatch match = match_dimension(e, e_new, m, ns);
    if (!match.feasible) return {};
    for (int32_t r = 0; r < m; ++r) partial[static_cast<std::size_t>(r) * S + s] = match.tuple_index[r];
    for (int32_t i : match.new_tuples) {
      std::fill(t.begin(), t.end(), kNoTrack);
      t[s] = i;
      partial.insert(partial.end(), t.begin(), t.end());
    }
  }
  return partial;
}

SolutionSD solve_two_sensors(const CostTensorSD& c) {
  const int32_t n0 = c.n[0], n1 = c.n[1];
  std::vector<double> e(static_cast<std::size_t>(n0) * (n1 + 1)), e_new(n1);
  for (int32_t i = 0; i < n0; ++i)
    for (int32_t j = 0; j <= n1; ++j)
      e[static_cast<std::size_t>(i) * (n1 + 1) + j] = c.cost[i * c.stride[0] + j];
  for (int32_t j = 0; j < n1; ++j) e_new[j] = c.cost[n0 * c.stride[0] + j];
  const DimensionMatch match = match_dimension(e, e_new, n0, n1);
  SolutionSD sol;
  sol.S = 2;
  if (match.feasible) {
    for (int32_t i = 0; i < n0; ++i) sol.tuples.insert(sol.tuples.end(), {i, match.tuple_index[i]});
    for (int32_t j : match.new_tuples) sol.tuples.insert(sol.tuples.end(), {kNoTrack, j});
  }
  sol.summary.termination = match.feasible ? Termination::kOptimal : Termination::kInfeasible;
  finish_summary_sd(c, sol.tuples, match.feasible ? match.cost : kInf, sol.summary);
  return sol;
}

}  // namespace

SolutionSD solve_lagrangian_sd(const CostTensorSD& c, const LagrangianOptions& options) {
  options.validate();
  c.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const int32_t S = c.dims();
  if (S == 2) {
    SolutionSD sol = solve_two_sensors(c);
    sol.summary.wall_time_s = seconds_since(t0);
    return sol;
  }
  const int32_t n0 = c.n[0], n1 = c.n[1];
  const std::size_t R = c.stride[1];  // block of sensors 3 … S for one (i_1, i_2)
  // μ_s(i) for s ≥ 3 (positions 2 … S−1), the dummy's entry fixed at 0; the driver's flat μ lists
  // them sensor by sensor from offset[s].
  std::vector<std::vector<double>> mu(S);
  std::vector<std::size_t> offset(S, 0);
  std::size_t flat = 0;
  for (int32_t s = 0; s < S; ++s) {
    mu[s].assign(static_cast<std::size_t>(c.n[s]) + 1, 0.0);
    offset[s] = flat;
    if (s >= 2) flat += c.n[s];
  }

  std::vector<int32_t> best, pairs;
  std::vector<double> p, d(static_cast<std::size_t>(n0 + 1) * (n1 + 1)), e, e_new;
  std::vector<std::size_t> arg(d.size());
  SolutionSD sol;
  sol.S = S;

  SubgradientProblem problem;
  problem.zero_subgradient_is_optimal = true;  // the relaxed constraints are equalities
  problem.dual = [&](const std::vector<double>& m, double& bound, std::vector<double>& g) {
    for (int32_t s = 2; s < S; ++s)
      for (int32_t i = 0; i < c.n[s]; ++i) mu[s][i] = m[offset[s] + i];
    // d(i_1, i_2) = min over the tail of c̃ (Deb et al. Eq. 12), parallel over i_1.
    tail_penalty(c, mu, 2, p);
    parallel_for_range(static_cast<std::size_t>(n0) + 1, 2, [&](std::size_t b, std::size_t end) {
      for (std::size_t i = b; i < end; ++i)
        for (int32_t j = 0; j <= n1; ++j) {
          const std::size_t k = i * (n1 + 1) + j;
          d[k] = block_min(c.cost.data() + i * c.stride[0] + j * c.stride[1], p.data(), R, arg[k]);
        }
    });
    // Tuples whose first two indices are dummies are unconstrained in the relaxed problem.
    const float* dd = c.cost.data() + static_cast<std::size_t>(n0) * c.stride[0] +
                      static_cast<std::size_t>(n1) * c.stride[1];
    double free_sum = 0.0;
    std::vector<std::size_t> free_chosen;
    for (std::size_t r = 0; r + 1 < R; ++r) {  // r = R−1 is the all-dummy tuple
      const double v = static_cast<double>(dd[r]) - p[r];
      if (v < 0.0) {
        free_sum += v;
        free_chosen.push_back(r);
      }
    }
    e.assign(static_cast<std::size_t>(n0) * (n1 + 1), 0.0);
    std::copy(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(e.size()), e.begin());
    e_new.assign(d.begin() + static_cast<std::ptrdiff_t>(e.size()),
                 d.begin() + static_cast<std::ptrdiff_t>(e.size()) + n1);
    const DimensionMatch lap = match_dimension(e, e_new, n0, n1);
    if (!lap.feasible) return false;
    double mu_sum = 0.0;
    for (int32_t s = 2; s < S; ++s)
      for (int32_t i = 0; i < c.n[s]; ++i) mu_sum += mu[s][i];
    bound = lap.cost + free_sum + mu_sum;

    // The relaxed solution's tuples: g_s(i) = 1 − uses of index i, and the (i_1, i_2) pairs.
    std::vector<int32_t> t(S);
    pairs.clear();
    std::fill(g.begin(), g.end(), 1.0);
    auto use_tail = [&](std::size_t r) {
      decode_tail(c, 2, r, t.data());
      for (int32_t s = 2; s < S; ++s)
        if (t[s] >= 0) g[offset[s] + t[s]] -= 1.0;
    };
    for (int32_t i = 0; i < n0; ++i) {
      const int32_t j = lap.tuple_index[i];
      use_tail(arg[static_cast<std::size_t>(i) * (n1 + 1) + (j < 0 ? n1 : j)]);
      pairs.insert(pairs.end(), {i, j});
      pairs.insert(pairs.end(), S - 2, kNoTrack);
    }
    for (int32_t j : lap.new_tuples) {
      use_tail(arg[static_cast<std::size_t>(n0) * (n1 + 1) + j]);
      pairs.insert(pairs.end(), {kNoTrack, j});
      pairs.insert(pairs.end(), S - 2, kNoTrack);
    }
    for (std::size_t r : free_chosen) use_tail(r);
    return true;
  };
  // Feasible recovery and polish → upper bound.
  problem.primal = [&](const std::vector<double>&, double incumbent) {
    std::vector<int32_t> feasible = recover(c, mu, std::move(pairs));
    if (feasible.empty() || !is_valid_assignment_sd(c, feasible)) return incumbent;
    if (options.local_search) polish_sd(c, feasible, options.local_search_options);
    const double ub = assignment_cost_sd(c, feasible);
    if (!(ub < incumbent)) return incumbent;
    best = std::move(feasible);
    return ub;
  };
  const SubgradientResult run = run_subgradient(problem, std::vector<double>(flat, 0.0), options, t0);
  const double lower = run.lower_bound;
  const Termination termination = run.termination;
  const int64_t iterations = run.iterations;
  sol.tuples = std::move(best);
  sol.summary.iterations = iterations;
  sol.summary.termination = termination;
  finish_summary_sd(c, sol.tuples,
                    std::isfinite(lower) || lower > 0 ? lower : std::numeric_limits<double>::quiet_NaN(),
                    sol.summary);
  if (!sol.summary.feasible) sol.summary.termination = Termination::kInfeasible;
  sol.summary.message = std::string("S-D relaxation, step rule ") + enum_name(options.step_rule);
  sol.summary.wall_time_s = seconds_since(t0);
  return sol;
}

}  // namespace trackassoc
