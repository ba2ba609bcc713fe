#include "kernels/assignment/clique_cuts.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "kernels/assignment/lagrangian_subgradient.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void CliqueCutOptions::validate() const {
  require(max_rounds >= 0, "CliqueCutOptions.max_rounds", "must be >= 0");
  require(iterations_per_round >= 1, "CliqueCutOptions.iterations_per_round", "must be >= 1");
  require(cuts_per_round >= 1, "CliqueCutOptions.cuts_per_round", "must be >= 1");
  require(stall_rounds >= 1, "CliqueCutOptions.stall_rounds", "must be >= 1");
  require(theta > 0.0 && theta <= 2.0, "CliqueCutOptions.theta", "must be in (0, 2]");
}

void add_clique_penalty(const CostTensor3& b, const Tuple3& r, double delta, std::vector<double>& w) {
  const int32_t i = r[0], j = r[1], k = r[2];
  for (int32_t q = 0; q < b.n3; ++q) w[b.index(i, j, q)] += delta;  // (i, j, ·), r included
  for (int32_t q = 0; q < b.n2; ++q)
    if (q != j) w[b.index(i, q, k)] += delta;  // (i, ·, k)
  for (int32_t q = 0; q < b.n1; ++q)
    if (q != i) w[b.index(q, j, k)] += delta;  // (·, j, k)
}

int clique_load(const Tuple3& r, const std::vector<int32_t>& row_j, const std::vector<int32_t>& row_k,
                const std::vector<int32_t>& owner_of_j) {
  // Members with r's i: the one tuple of row i, if it shares j or k. Members with r's j but not
  // its i: the tuple owning j, if it shares k. Members with neither share only k: not in Q(r).
  int load = (row_j[r[0]] == r[1] || row_k[r[0]] == r[2]) ? 1 : 0;
  const int32_t owner = owner_of_j[r[1]];
  if (owner >= 0 && owner != r[0] && row_k[owner] == r[2]) ++load;
  return load;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRoundTol = 1e-7;

struct TupleLess {
  bool operator()(const Tuple3& a, const Tuple3& b) const { return a < b; }
};

}  // namespace

CliqueRelaxation run_clique_relaxation(const CanonicalProblem3& p, const LagrangianOptions& options,
                                       const CliqueCutOptions& cuts, const LagrangianRun& start,
                                       std::chrono::steady_clock::time_point t0) {
  options.validate();
  cuts.validate();
  const CostTensor3& b = p.tensor;
  const int32_t n1 = b.n1, n2 = b.n2, n3 = b.n3;
  const bool equality = p.k_equality();
  CliqueRelaxation out;
  out.mu = start.best_multipliers;
  out.lower_bound = start.lower_bound;
  out.upper_bound = start.upper_bound;
  out.best_tuples = start.best_tuples;
  out.termination = start.termination;
  if (n1 == 0 || out.mu.empty()) return out;

  std::vector<double> w(b.cost.begin(), b.cost.end()), applied;  // w at λ = `applied`
  std::vector<double> c(static_cast<std::size_t>(n1) * n2), recovery;
  std::vector<int32_t> arg(static_cast<std::size_t>(n1) * n2), count(n3), row_j(n1), row_k(n1),
      owner_of_j(n2);
  std::map<Tuple3, int, TupleLess> candidates;  // violated cuts seen in this round, with their frequency
  std::set<Tuple3, TupleLess> in_pool;
  LapResult lap;

  SubgradientProblem problem;
  problem.integer_costs = p.integer_costs;
  problem.nonnegative = true;  // λ ≥ 0; μ too unless the k constraints are equalities
  problem.free_sign_count = equality ? static_cast<std::size_t>(n3) : 0;
  problem.dual = [&](const std::vector<double>& m, double& bound, std::vector<double>& g) {
    const std::size_t ncuts = out.roots.size();
    double lambda_sum = 0.0;
    for (std::size_t q = 0; q < ncuts; ++q) {
      const double lam = m[n3 + q];
      lambda_sum += lam;
      if (lam != applied[q]) {
        add_clique_penalty(b, out.roots[q], lam - applied[q], w);
        applied[q] = lam;
      }
    }
    reduce_over_k(w.data(), n1, n2, n3, m, c, arg);
    lap = solve_lap(c, n1, n2);
    if (!lap.feasible) return false;
    double mu_sum = 0.0;
    for (int32_t k = 0; k < n3; ++k) mu_sum += m[k];
    bound = lap.cost - mu_sum - lambda_sum;  // unrounded, so the ascent sees fractional progress
    std::fill(count.begin(), count.end(), 0);
    std::fill(owner_of_j.begin(), owner_of_j.end(), -1);
    for (int32_t i = 0; i < n1; ++i) {
      row_j[i] = lap.row_to_col[i];
      row_k[i] = arg[static_cast<std::size_t>(i) * n2 + row_j[i]];
      owner_of_j[row_j[i]] = i;
      ++count[row_k[i]];
    }
    for (int32_t k = 0; k < n3; ++k) {
      g[k] = count[k] - 1.0;
      if (!equality && m[k] <= 0.0 && g[k] < 0.0) g[k] = 0.0;
    }
    for (std::size_t q = 0; q < ncuts; ++q) {
      g[n3 + q] = clique_load(out.roots[q], row_j, row_k, owner_of_j) - 1.0;
      if (m[n3 + q] <= 0.0 && g[n3 + q] < 0.0) g[n3 + q] = 0.0;
    }
    // Separation: rows sharing a k give the two violated cliques Q((i1, j2, k)), Q((i2, j1, k)).
    std::vector<std::vector<int32_t>> rows_of_k(n3);
    for (int32_t i = 0; i < n1; ++i)
      if (count[row_k[i]] > 1) rows_of_k[row_k[i]].push_back(i);
    for (int32_t k = 0; k < n3; ++k)
      for (std::size_t x = 0; x < rows_of_k[k].size(); ++x)
        for (std::size_t y = x + 1; y < rows_of_k[k].size(); ++y) {
          const int32_t i1 = rows_of_k[k][x], i2 = rows_of_k[k][y];
          for (const Tuple3& r : {Tuple3{i1, row_j[i2], k}, Tuple3{i2, row_j[i1], k}})
            if (!in_pool.count(r)) ++candidates[r];
        }
    return true;
  };
  problem.primal = [&](const std::vector<double>&, double) {
    std::vector<Tuple3> feasible = recover_feasible(b, lap.row_to_col, recovery);
    if (!feasible.empty()) {
      if (options.local_search) polish_canonical(b, feasible, options.local_search_options);
      const double ub = tuples_cost(b, feasible);
      if (ub < out.upper_bound) {
        out.upper_bound = ub;
        out.best_tuples = std::move(feasible);
      }
    }
    return out.upper_bound;
  };

  auto rounded = [&](double x) {
    return p.integer_costs ? std::ceil(x - kRoundTol * std::max(1.0, std::abs(x))) : x;
  };
  double best_raw = -kInf, first_raw = -kInf;
  auto closed = [&] {
    const double gap = out.upper_bound - out.lower_bound;
    return gap <= options.absolute_gap_tolerance || (p.integer_costs && gap < 1.0 - kRoundTol);
  };
  auto elapsed = [&] { return seconds_since(t0); };

  LagrangianOptions round = options;
  round.max_iterations = cuts.iterations_per_round;
  round.theta = cuts.theta;
  round.min_theta = std::min(round.min_theta, round.theta);
  std::vector<double> m = out.mu, gscratch(n3);
  {
    double bound = 0.0;  // one evaluation at the start's μ seeds the pool
    applied.clear();
    if (!problem.dual(m, bound, gscratch)) return out;
  }
  int stall = 0;
  for (int rd = 0; rd < cuts.max_rounds && !closed() && elapsed() < options.time_limit_s; ++rd) {
    // New cuts: the most frequent candidates first (ties in tuple order), λ = 0.
    std::vector<std::pair<int, Tuple3>> ranked;
    for (const auto& [r, f] : candidates) ranked.push_back({-f, r});
    std::sort(ranked.begin(), ranked.end());
    candidates.clear();
    const std::size_t add =
        std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(cuts.cuts_per_round));
    for (std::size_t q = 0; q < add; ++q) {
      out.roots.push_back(ranked[q].second);
      in_pool.insert(ranked[q].second);
      applied.push_back(0.0);
      m.push_back(0.0);
    }
    if (add == 0 && stall > 0) break;  // nothing new to relax and no progress on the pool
    const SubgradientResult r = run_subgradient(problem, m, round, t0);
    ++out.rounds;
    out.iterations += r.iterations;
    if (r.termination == Termination::kInfeasible) break;
    if (r.lower_bound > best_raw) {
      best_raw = r.lower_bound;
      out.lower_bound = std::max(out.lower_bound, rounded(best_raw));
      out.mu.assign(r.best_multipliers.begin(), r.best_multipliers.begin() + n3);
      out.lambda.assign(r.best_multipliers.begin() + n3, r.best_multipliers.end());
      stall = 0;
    } else if (++stall >= cuts.stall_rounds) {
      break;
    }
    m = r.best_multipliers;
    if (out.rounds == 1) first_raw = r.lower_bound;
    // Integer costs: give up when the pace so far cannot lift the rounded bound in the rounds left.
    if (p.integer_costs && out.rounds >= 3) {
      const double pace = (best_raw - first_raw) / (out.rounds - 1);
      const double need = std::floor(best_raw + kRoundTol) + 1.0 - best_raw;
      if (!(pace > 0.0) || need > pace * (cuts.max_rounds - out.rounds)) break;
    }
  }
  // w rebuilt exactly from the best λ (cuts added after it get λ = 0).
  out.lambda.resize(out.roots.size(), 0.0);
  out.penalised.assign(b.cost.begin(), b.cost.end());
  out.lambda_sum = 0.0;
  for (std::size_t q = 0; q < out.roots.size(); ++q)
    if (out.lambda[q] > 0.0) {
      add_clique_penalty(b, out.roots[q], out.lambda[q], out.penalised);
      out.lambda_sum += out.lambda[q];
    }
  if (closed())
    out.termination = Termination::kOptimal;
  else if (elapsed() >= options.time_limit_s)
    out.termination = Termination::kTimeLimit;
  else
    out.termination = Termination::kIterationLimit;
  return out;
}

}  // namespace trackassoc
