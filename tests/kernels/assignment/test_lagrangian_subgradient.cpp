// The subgradient driver (kernels/assignment/lagrangian_subgradient.hpp) on a 2×2×2 instance whose dual is
// worked out by hand, directly and through the 3-D relaxation:
//
//   b_ijk = a_ij + 10·k,  a = [[1.5, 4], [3, 2.5]].
//
// Every assignment uses k = 0 once and k = 1 once, so the optimum is LAP(a) + 10 = 4 + 10 = 14.
// Relaxing the k constraints: c_ij = a_ij + min(μ0, 10 + μ1), and with 2 min(p, q) − p − q = −|p − q|
//   L(μ) = LAP(a) + 2 min(μ0, 10 + μ1) − μ0 − μ1 = 14 − |μ0 − μ1 − 10|,
// maximal (= 14, no duality gap) on the line μ0 − μ1 = 10. At μ = 0 both pairs take k = 0:
// g = (1, −1), ‖g‖² = 2, L = 4, and the recovered solution costs 14; the Polyak step with θ = 1 is
// 1·(14 − 4)/2 = 5, so μ = (5, −5) and L = 14 at the second iteration.
#include <gtest/gtest.h>

#include <cmath>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/lagrangian_subgradient.hpp"

namespace trackassoc {
namespace {

constexpr double kOptimum = 14.0;

// The hand-derived dual above: L(μ) and g (the k of each pair: 0 unless 10 + μ1 < μ0).
SubgradientProblem hand_problem() {
  SubgradientProblem p;
  p.dual = [](const std::vector<double>& mu, double& bound, std::vector<double>& g) {
    const bool k1 = 10.0 + mu[1] < mu[0];
    bound = 4.0 + 2.0 * std::min(mu[0], 10.0 + mu[1]) - mu[0] - mu[1];
    g = k1 ? std::vector<double>{-1.0, 1.0} : std::vector<double>{1.0, -1.0};
    return true;
  };
  p.primal = [](const std::vector<double>&, double incumbent) { return std::min(incumbent, kOptimum); };
  return p;
}

TEST(LagrangianSubgradient, PolyakReachesTheHandComputedDualInTwoSteps) {
  LagrangianOptions o;
  o.theta = 1.0;
  o.min_theta = 1e-6;
  std::vector<SubgradientIterate> trace;
  const SubgradientResult r =
      run_subgradient(hand_problem(), {0.0, 0.0}, o, std::chrono::steady_clock::now(), &trace);
  EXPECT_EQ(r.termination, Termination::kOptimal);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_EQ(r.lower_bound, kOptimum);
  EXPECT_EQ(r.upper_bound, kOptimum);
  EXPECT_EQ(r.best_multipliers, (std::vector<double>{5.0, -5.0}));
  ASSERT_EQ(trace.size(), 2u);
  EXPECT_EQ(trace[0].bound, 4.0);
  EXPECT_EQ(trace[0].step, 5.0);
  EXPECT_EQ(trace[1].bound, kOptimum);
}

TEST(LagrangianSubgradient, TheThreeDRelaxationSolvesTheSameInstance) {
  CostTensor3 b(2, 2, 2);
  const double a[2][2] = {{1.5, 4.0}, {3.0, 2.5}};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) b.at(i, j, k) = static_cast<float>(a[i][j] + 10.0 * k);
  LagrangianOptions o;
  o.theta = 1.0;
  const LagrangianRun run = run_lagrangian(make_canonical(b), o);
  EXPECT_EQ(run.termination, Termination::kOptimal);
  EXPECT_EQ(run.iterations, 2);
  EXPECT_EQ(run.lower_bound, kOptimum);
  EXPECT_EQ(run.upper_bound, kOptimum);
  ASSERT_EQ(run.best_multipliers.size(), 2u);
  EXPECT_EQ(run.best_multipliers[0] - run.best_multipliers[1], 10.0);
}

// Every rule and θ: L(μ) never exceeds the optimum, the best bound is the running maximum of L,
// and θ only falls.
TEST(LagrangianSubgradient, BoundsStayBelowTheOptimumAndTheBestBoundIsMonotone) {
  for (StepRule rule : {StepRule::kPolyak, StepRule::kDiminishing, StepRule::kDeflected})
    for (double theta : {2.0, 1.3, 0.7}) {
      SCOPED_TRACE(std::string(enum_name(rule)) + " theta " + std::to_string(theta));
      LagrangianOptions o;
      o.step_rule = rule;
      o.theta = theta;
      o.min_theta = 1e-6;
      o.max_iterations = 200;
      std::vector<SubgradientIterate> trace;
      const SubgradientResult r =
          run_subgradient(hand_problem(), {0.0, 0.0}, o, std::chrono::steady_clock::now(), &trace);
      ASSERT_EQ(static_cast<int64_t>(trace.size()), r.iterations);
      double best = -std::numeric_limits<double>::infinity(), last_theta = theta;
      for (const SubgradientIterate& t : trace) {
        EXPECT_LE(t.bound, kOptimum);
        best = std::max(best, t.bound);
        EXPECT_EQ(t.lower_bound, best);
        EXPECT_LE(t.theta, last_theta);
        last_theta = t.theta;
      }
      EXPECT_EQ(r.lower_bound, best);
      EXPECT_LE(r.lower_bound, kOptimum);
      // Every rule improves on L(0) = 4 but the deflected one at θ = 2, whose steps on this dual
      // (14 − |μ0 − μ1 − 10|) never land closer to the kink than μ = 0: its best bound stays L(0)
      // over the 200 iterations (measured).
      if (rule == StepRule::kDeflected && theta == 2.0)
        EXPECT_EQ(r.lower_bound, 4.0);
      else
        EXPECT_GT(r.lower_bound, 4.0);
    }
}

// The options of the problem: sign constraints, what g = 0 means, an infeasible subproblem.
TEST(LagrangianSubgradient, ProjectionZeroSubgradientAndInfeasibility) {
  LagrangianOptions o;
  o.theta = 1.0;
  o.relative_gap_tolerance = 0.0;
  o.absolute_gap_tolerance = 1e-12;
  SubgradientProblem p = hand_problem();
  p.nonnegative = true;  // μ1 wants to go to −5; the projection keeps it at 0
  std::vector<SubgradientIterate> trace;
  SubgradientResult r = run_subgradient(p, {0.0, 0.0}, o, std::chrono::steady_clock::now(), &trace);
  ASSERT_GE(trace.size(), 2u);
  for (double m : r.multipliers) EXPECT_GE(m, 0.0);
  EXPECT_EQ(trace[1].bound, 4.0 + 2.0 * 5.0 - 5.0);  // μ = (5, 0): L = 9
  p.free_sign_count = 2;  // both exempt from the projection: the unconstrained ascent again
  r = run_subgradient(p, {0.0, 0.0}, o, std::chrono::steady_clock::now());
  EXPECT_EQ(r.best_multipliers, (std::vector<double>{5.0, -5.0}));
  EXPECT_EQ(r.lower_bound, kOptimum);

  SubgradientProblem flat;  // g = 0 with L = 3 < UB = 5
  flat.dual = [](const std::vector<double>&, double& bound, std::vector<double>& g) {
    bound = 3.0;
    std::fill(g.begin(), g.end(), 0.0);
    return true;
  };
  flat.primal = [](const std::vector<double>&, double incumbent) { return std::min(incumbent, 5.0); };
  flat.zero_subgradient_is_optimal = true;
  r = run_subgradient(flat, {0.0}, o, std::chrono::steady_clock::now());
  EXPECT_EQ(r.termination, Termination::kOptimal);
  EXPECT_EQ(r.iterations, 1);
  flat.zero_subgradient_is_optimal = false;
  r = run_subgradient(flat, {0.0}, o, std::chrono::steady_clock::now());
  EXPECT_EQ(r.termination, Termination::kIterationLimit);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(r.lower_bound, 3.0);

  SubgradientProblem none = flat;
  none.dual = [](const std::vector<double>&, double&, std::vector<double>&) { return false; };
  r = run_subgradient(none, {0.0}, o, std::chrono::steady_clock::now());
  EXPECT_EQ(r.termination, Termination::kInfeasible);
  EXPECT_EQ(r.lower_bound, std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace trackassoc
