#include "kernels/lagrangian_relaxation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "kernels/error.hpp"
#include "kernels/lap.hpp"
#include "kernels/parallel.hpp"

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

// c_ij = min_k (b_ijk + μ_k) and its argmin (Pattipati Eq. 16). Double, so the bound is exact up to
// the LAP's own rounding. Parallel over i; each (i, j) is computed by one task alone.
void reduce_over_k(const CostTensor3& b, const std::vector<double>& mu, std::vector<double>& c,
                   std::vector<int32_t>& arg) {
  const int32_t n2 = b.n2, n3 = b.n3;
  parallel_for_range(static_cast<std::size_t>(b.n1), 8, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (int32_t j = 0; j < n2; ++j) {
        const float* row = b.cost.data() + (i * n2 + j) * n3;
        double best = kInf;
        for (int32_t k = 0; k < n3; ++k) best = std::min(best, static_cast<double>(row[k]) + mu[k]);
        int32_t kbest = 0;
        while (kbest < n3 - 1 && static_cast<double>(row[kbest]) + mu[kbest] != best) ++kbest;
        c[i * n2 + j] = best;
        arg[i * n2 + j] = kbest;
      }
  });
}

// Matches the pairs (i, j_i) to k by a LAP on b_{i j_i k}; returns the tuples, or empty if none
// of finite cost exists.
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

}  // namespace

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
  run.best_multipliers = mu;
  std::vector<double> c(static_cast<std::size_t>(n1) * n2), g(n3), direction(n3, 0.0), recovery;
  std::vector<int32_t> arg(static_cast<std::size_t>(n1) * n2), count(n3);
  double theta = options.theta;
  int since_better = 0;
  double delta0 = -1.0;
  const double round_tol = 1e-7;

  auto converged = [&]() {
    const double abs_gap = run.upper_bound - run.lower_bound;
    if (abs_gap <= options.absolute_gap_tolerance) return Termination::kOptimal;
    if (p.integer_costs && abs_gap < 1.0 - round_tol) return Termination::kOptimal;
    if (abs_gap / std::max(std::abs(run.upper_bound), 1e-9) <= options.relative_gap_tolerance)
      return Termination::kGapTolerance;
    return Termination::kIterationLimit;  // "not yet"
  };

  for (int iter = 0; iter < options.max_iterations; ++iter) {
    run.iterations = iter + 1;
    reduce_over_k(b, mu, c, arg);
    const LapResult lap = solve_lap(c, n1, n2);
    if (!lap.feasible) {
      // No (i, j) matching of finite cost even with k free: the problem is infeasible.
      run.termination = Termination::kInfeasible;
      run.lower_bound = kInf;
      return run;
    }
    double mu_sum = 0.0;
    for (int32_t k = 0; k < n3; ++k) mu_sum += mu[k];
    double bound = lap.cost - mu_sum;  // L(μ), Pattipati Eq. 14
    if (p.integer_costs) bound = std::ceil(bound - round_tol * std::max(1.0, std::abs(bound)));
    if (bound > run.lower_bound) {
      run.lower_bound = bound;
      run.best_multipliers = mu;
      since_better = 0;
    } else if (++since_better >= options.theta_patience) {
      theta *= 0.5;
      since_better = 0;
    }

    // Feasible recovery (and polish) → upper bound.
    std::vector<Tuple3> feasible = recover_feasible(b, lap.row_to_col, recovery);
    if (!feasible.empty()) {
      if (options.local_search) polish_canonical(b, feasible, options.local_search_options);
      const double ub = tuples_cost(b, feasible);
      if (ub < run.upper_bound) {
        run.upper_bound = ub;
        run.best_tuples = std::move(feasible);
      }
    }

    const Termination t = converged();
    if (t != Termination::kIterationLimit && std::isfinite(run.upper_bound)) {
      run.termination = t;
      return run;
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > options.time_limit_s) {
      run.termination = Termination::kTimeLimit;
      return run;
    }
    if (theta < options.min_theta) break;

    // Subgradient g_k = Σ x_·· k − 1, projected for the "≤ 1" case (μ_k = 0 and g_k < 0 cannot move).
    std::fill(count.begin(), count.end(), 0);
    for (int32_t i = 0; i < n1; ++i) ++count[arg[static_cast<std::size_t>(i) * n2 + lap.row_to_col[i]]];
    double g2 = 0.0;
    for (int32_t k = 0; k < n3; ++k) {
      g[k] = count[k] - 1.0;
      if (!equality && mu[k] <= 0.0 && g[k] < 0.0) g[k] = 0.0;
      g2 += g[k] * g[k];
    }
    if (g2 == 0.0) {
      // The relaxed solution satisfies the relaxed constraints (with complementary slackness on
      // the "≤" ones): it is optimal, and recovery found it.
      run.lower_bound = std::max(run.lower_bound, std::min(run.upper_bound, bound));
      run.termination = Termination::kOptimal;
      if (run.upper_bound - run.lower_bound > options.absolute_gap_tolerance) run.termination = converged();
      if (run.termination == Termination::kIterationLimit) break;
      return run;
    }
    // Target: the best upper bound (if none yet, 5 % above the bound).
    const double target =
        std::isfinite(run.upper_bound) ? run.upper_bound : bound + 0.05 * std::max(1.0, std::abs(bound));
    const double gap = std::max(target - bound, 1e-12 * std::max(1.0, std::abs(bound)));
    if (delta0 < 0.0) delta0 = gap;
    double step = 0.0;
    switch (options.step_rule) {
      case StepRule::kPolyak:
        direction = g;
        step = theta * gap / g2;
        break;
      case StepRule::kDiminishing:
        direction = g;
        step = options.theta * delta0 / (g2 * std::sqrt(iter + 1.0));
        break;
      case StepRule::kDeflected: {
        double gd = 0.0, dd = 0.0;
        for (int32_t k = 0; k < n3; ++k) {
          gd += g[k] * direction[k];
          dd += direction[k] * direction[k];
        }
        const double beta = (iter > 0 && dd > 0.0) ? std::max(0.0, -1.5 * gd / dd) : 0.0;
        double d2 = 0.0;
        for (int32_t k = 0; k < n3; ++k) {
          direction[k] = g[k] + beta * direction[k];
          d2 += direction[k] * direction[k];
        }
        step = theta * gap / std::max(d2, 1e-300);
        break;
      }
    }
    for (int32_t k = 0; k < n3; ++k) {
      mu[k] += step * direction[k];
      if (!equality) mu[k] = std::max(mu[k], 0.0);
    }
  }
  run.termination = std::isfinite(run.upper_bound) ? Termination::kIterationLimit : Termination::kInfeasible;
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
  s.summary.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace trackassoc
