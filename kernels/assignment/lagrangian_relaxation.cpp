#include "kernels/assignment/lagrangian_relaxation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "kernels/assignment/lagrangian_subgradient.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void LagrangianOptions::validate() const {
  require(max_iterations >= 1, "LagrangianOptions.max_iterations",
          "must be >= 1, got " + std::to_string(max_iterations));
  require(relative_gap_tolerance >= 0.0 && std::isfinite(relative_gap_tolerance),
          "LagrangianOptions.relative_gap_tolerance", "must be finite and >= 0");
  require(absolute_gap_tolerance >= 0.0 && std::isfinite(absolute_gap_tolerance),
          "LagrangianOptions.absolute_gap_tolerance", "must be finite and >= 0");
  require(time_limit_s > 0.0 && !std::isnan(time_limit_s), "LagrangianOptions.time_limit_s", "must be > 0");
  require(theta > 0.0 && theta <= 2.0, "LagrangianOptions.theta",
          "must be in (0, 2], got " + std::to_string(theta));
  require(theta_patience >= 1, "LagrangianOptions.theta_patience", "must be >= 1");
  require(min_theta > 0.0 && min_theta <= theta, "LagrangianOptions.min_theta", "must be in (0, theta]");
  local_search_options.validate();
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <class T>
void reduce_over_k_impl(const T* w, int32_t n1, int32_t n2, int32_t n3, const std::vector<double>& mu,
                        std::vector<double>& c, std::vector<int32_t>& arg) {
  parallel_for_range(static_cast<std::size_t>(n1), 8, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (int32_t j = 0; j < n2; ++j) {
        const T* row = w + (i * n2 + j) * n3;
        double best = kInf;
        for (int32_t k = 0; k < n3; ++k) best = std::min(best, static_cast<double>(row[k]) + mu[k]);
        int32_t kbest = 0;
        while (kbest < n3 - 1 && static_cast<double>(row[kbest]) + mu[kbest] != best) ++kbest;
        c[i * n2 + j] = best;
        arg[i * n2 + j] = kbest;
      }
  });
}

}  // namespace

void reduce_over_k(const float* w, int32_t n1, int32_t n2, int32_t n3, const std::vector<double>& mu,
                   std::vector<double>& c, std::vector<int32_t>& arg) {
  reduce_over_k_impl(w, n1, n2, n3, mu, c, arg);
}

void reduce_over_k(const double* w, int32_t n1, int32_t n2, int32_t n3, const std::vector<double>& mu,
                   std::vector<double>& c, std::vector<int32_t>& arg) {
  reduce_over_k_impl(w, n1, n2, n3, mu, c, arg);
}

std::vector<Tuple3> recover_feasible(const CostTensor3& b, const std::vector<int32_t>& row_to_col,
                                     std::vector<double>& matrix) {
  const int32_t m = b.n1, n3 = b.n3;
  matrix.resize(static_cast<std::size_t>(m) * n3);
  for (int32_t i = 0; i < m; ++i) {
    const float* row = b.cost.data() + (static_cast<std::size_t>(i) * b.n2 + row_to_col[i]) * n3;
    for (int32_t k = 0; k < n3; ++k) matrix[static_cast<std::size_t>(i) * n3 + k] = row[k];
  }
  const LapResult lap = solve_lap(matrix, m, n3);
  if (!lap.feasible) return {};
  std::vector<Tuple3> t(m);
  for (int32_t i = 0; i < m; ++i) t[i] = {i, row_to_col[i], lap.row_to_col[i]};
  return t;
}

double tuples_cost(const CostTensor3& b, const std::vector<Tuple3>& t) {
  double s = 0.0;
  for (const auto& x : t) s += b.at(x[0], x[1], x[2]);
  return s;
}

LagrangianRun run_lagrangian(const CanonicalProblem3& p, const LagrangianOptions& options,
                             const std::vector<double>& initial_multipliers) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const CostTensor3& b = p.tensor;
  LagrangianRun run;
  if (b.n1 == 0) {
    run.upper_bound = run.lower_bound = 0.0;
    run.termination = Termination::kOptimal;
    return run;
  }
  const int32_t n1 = b.n1, n2 = b.n2, n3 = b.n3;
  const bool equality = p.k_equality();
  std::vector<double> mu(n3, 0.0);
  if (!initial_multipliers.empty()) {
    require(static_cast<int32_t>(initial_multipliers.size()) == n3, "run_lagrangian",
            "multiplier size mismatch");
    mu = initial_multipliers;
  }
  std::vector<double> c(static_cast<std::size_t>(n1) * n2), recovery;
  std::vector<int32_t> arg(static_cast<std::size_t>(n1) * n2), count(n3);
  LapResult lap;
  const double round_tol = 1e-7;

  SubgradientProblem problem;
  problem.integer_costs = p.integer_costs;
  problem.nonnegative = !equality;
  problem.dual = [&](const std::vector<double>& m, double& bound, std::vector<double>& g) {
    reduce_over_k(b.cost.data(), n1, n2, n3, m, c, arg);
    lap = solve_gated_lap(c, n1, n2);  // sparse when the tensor is gated (kernels/assignment/lap_sparse.hpp)
    // No (i, j) matching of finite cost even with k free: the problem is infeasible.
    if (!lap.feasible) return false;
    double mu_sum = 0.0;
    for (int32_t k = 0; k < n3; ++k) mu_sum += m[k];
    bound = lap.cost - mu_sum;  // L(μ), Pattipati Eq. 14
    if (p.integer_costs) bound = std::ceil(bound - round_tol * std::max(1.0, std::abs(bound)));
    // Subgradient g_k = Σ x_·· k − 1, projected for the "≤ 1" case (μ_k = 0 and g_k < 0 cannot move).
    std::fill(count.begin(), count.end(), 0);
    for (int32_t i = 0; i < n1; ++i) ++count[arg[static_cast<std::size_t>(i) * n2 + lap.row_to_col[i]]];
    for (int32_t k = 0; k < n3; ++k) {
      g[k] = count[k] - 1.0;
      if (!equality && m[k] <= 0.0 && g[k] < 0.0) g[k] = 0.0;
    }
    return true;
  };
  // Feasible recovery (and polish) → upper bound.
  problem.primal = [&](const std::vector<double>&, double incumbent) {
    std::vector<Tuple3> feasible = recover_feasible(b, lap.row_to_col, recovery);
    if (feasible.empty()) return incumbent;
    if (options.local_search) polish_canonical(b, feasible, options.local_search_options);
    const double ub = tuples_cost(b, feasible);
    if (!(ub < incumbent)) return incumbent;
    run.best_tuples = std::move(feasible);
    return ub;
  };
  SubgradientResult r = run_subgradient(problem, std::move(mu), options, t0);
  run.upper_bound = r.upper_bound;
  run.lower_bound = r.lower_bound;
  run.best_multipliers = std::move(r.best_multipliers);
  run.iterations = r.iterations;
  run.termination = r.termination;
  return run;
}

Solution3 solve_lagrangian3(const CostTensor3& cost, const LagrangianOptions& options) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const CanonicalProblem3 p = make_canonical(cost);
  const LagrangianRun run = run_lagrangian(p, options);
  Solution3 s;
  s.tuples = to_original(p, run.best_tuples);
  s.summary.iterations = run.iterations;
  s.summary.termination = run.termination;
  finish_summary(cost, s.tuples, run.lower_bound, s.summary);
  if (!s.summary.feasible) s.summary.termination = Termination::kInfeasible;
  s.summary.message = std::string("step rule ") + enum_name(options.step_rule) +
                      (p.padded ? "; dummy indices padded to n1+n2+n3" : "");
  s.summary.wall_time_s = seconds_since(t0);
  return s;
}

}  // namespace trackassoc
