#include "kernels/assignment/lagrangian_subgradient.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

SubgradientResult run_subgradient(const SubgradientProblem& problem, std::vector<double> mu,
                                  const LagrangianOptions& options,
                                  std::chrono::steady_clock::time_point start,
                                  std::vector<SubgradientIterate>* trace) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kRoundTol = 1e-7;
  const std::size_t m = mu.size();
  SubgradientResult run;
  run.best_multipliers = mu;
  std::vector<double> g(m, 0.0), direction(m, 0.0);
  double theta = options.theta, delta0 = -1.0;
  int since_better = 0;
  auto elapsed = [&] { return seconds_since(start); };
  auto converged = [&] {
    const double abs_gap = run.upper_bound - run.lower_bound;
    if (abs_gap <= options.absolute_gap_tolerance) return Termination::kOptimal;
    if (problem.integer_costs && abs_gap < 1.0 - kRoundTol) return Termination::kOptimal;
    if (abs_gap / std::max(std::abs(run.upper_bound), 1e-9) <= options.relative_gap_tolerance)
      return Termination::kGapTolerance;
    return Termination::kIterationLimit;  // "not yet"
  };
  auto record = [&](double bound, double step) {
    if (trace) trace->push_back({bound, run.lower_bound, run.upper_bound, theta, step});
  };
  auto finish = [&](Termination t) {
    run.termination = t;
    run.multipliers = std::move(mu);
    return std::move(run);
  };

  for (int iter = 0; iter < options.max_iterations; ++iter) {
    run.iterations = iter + 1;
    double bound = 0.0;
    if (!problem.dual(mu, bound, g)) {
      run.lower_bound = kInf;
      return finish(Termination::kInfeasible);
    }
    if (bound > run.lower_bound) {
      run.lower_bound = bound;
      run.best_multipliers = mu;
      since_better = 0;
    } else if (++since_better >= options.theta_patience) {
      theta *= 0.5;
      since_better = 0;
    }
    run.upper_bound = problem.primal(mu, run.upper_bound);

    double g2 = 0.0;
    for (std::size_t k = 0; k < m; ++k) g2 += g[k] * g[k];
    const Termination t = converged();
    if (t != Termination::kIterationLimit && std::isfinite(run.upper_bound)) {
      record(bound, 0.0);
      return finish(t);
    }
    if (g2 == 0.0) {
      record(bound, 0.0);
      if (problem.zero_subgradient_is_optimal) return finish(Termination::kOptimal);
      if (elapsed() > options.time_limit_s) return finish(Termination::kTimeLimit);
      break;
    }
    if (elapsed() > options.time_limit_s) {
      record(bound, 0.0);
      return finish(Termination::kTimeLimit);
    }
    if (theta < options.min_theta) {
      record(bound, 0.0);
      break;
    }

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
        for (std::size_t k = 0; k < m; ++k) {
          gd += g[k] * direction[k];
          dd += direction[k] * direction[k];
        }
        const double beta = (iter > 0 && dd > 0.0) ? std::max(0.0, -1.5 * gd / dd) : 0.0;
        double d2 = 0.0;
        for (std::size_t k = 0; k < m; ++k) {
          direction[k] = g[k] + beta * direction[k];
          d2 += direction[k] * direction[k];
        }
        step = theta * gap / std::max(d2, 1e-300);
        break;
      }
    }
    for (std::size_t k = 0; k < m; ++k) {
      mu[k] += step * direction[k];
      if (problem.nonnegative && k >= problem.free_sign_count) mu[k] = std::max(mu[k], 0.0);
    }
    record(bound, step);
  }
  return finish(std::isfinite(run.upper_bound) ? Termination::kIterationLimit : Termination::kInfeasible);
}

}  // namespace trackassoc
