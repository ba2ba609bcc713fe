// The S-D relaxation over listed tuples (kernels/assignment/sd/lagrangian_sd_tuples.hpp): a hand
// example where taking the cheapest tuple first is wrong and the bound closes the gap; the bound is
// valid and the solution within the reported gap against brute force on random sparse S = 3, 4, 5
// instances (the dense tensor with +inf off the list); two sensors are one exact LAP; bad lists are
// rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernels/assignment/sd/lagrangian_sd_tuples.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;

// The list with every singleton at `single`, plus the given tuples.
TupleListSD list_with_singletons(std::vector<int32_t> n, double single) {
  TupleListSD p;
  p.n = std::move(n);
  const int32_t S = p.dims();
  for (int32_t s = 0; s < S; ++s)
    for (int32_t i = 0; i < p.n[s]; ++i) {
      std::vector<int32_t> t(S, kNoTrack);
      t[s] = i;
      p.tuples.insert(p.tuples.end(), t.begin(), t.end());
      p.cost.push_back(single);
    }
  return p;
}

void add(TupleListSD& p, std::vector<int32_t> t, double cost) {
  p.tuples.insert(p.tuples.end(), t.begin(), t.end());
  p.cost.push_back(cost);
}

// The dense tensor of a list: +inf off the list.
CostTensorSD dense_of(const TupleListSD& p) {
  CostTensorSD c(p.n, std::numeric_limits<float>::infinity());
  const int32_t S = p.dims();
  for (std::size_t t = 0; t < p.size(); ++t)
    c.at(std::span<const int32_t>(&p.tuples[t * S], S)) = static_cast<float>(p.cost[t]);
  return c;
}

TEST(LagrangianSDTuples, CheapestTupleFirstIsWrongAndTheBoundSaysSo) {
  // Sensors a (2 tracks), b (2), c (1). (a0, b0, c0) costs −10, (a0, b1) and (a1, b0) −6 each.
  // Cheapest first: −10 and singletons (0) = −10. The optimum: the two pairs and c0 alone = −12,
  // and the LP is integral here, so the relaxation's bound is −12 too.
  TupleListSD p = list_with_singletons({2, 2, 1}, 0.0);
  add(p, {0, 0, 0}, -10.0);
  add(p, {0, 1, kNoTrack}, -6.0);
  add(p, {1, 0, kNoTrack}, -6.0);
  const SolutionSD s = solve_lagrangian_sd_tuples(p);
  ASSERT_TRUE(s.summary.feasible);
  EXPECT_DOUBLE_EQ(s.summary.objective, -12.0);
  EXPECT_NEAR(s.summary.lower_bound, -12.0, 1e-9);
  EXPECT_NEAR(s.summary.gap, 0.0, 1e-9);
  EXPECT_EQ(s.num_tuples(), 3u);
  EXPECT_TRUE(is_valid_assignment_sd(dense_of(p), s.tuples));
}

TEST(LagrangianSDTuples, CertifiedAgainstBruteForceOnRandomSparseLists) {
  const std::vector<std::vector<int32_t>> shapes{
      {3, 3, 3}, {4, 2, 3}, {3, 2, 3, 2}, {2, 3, 2, 3}, {2, 2, 2, 2, 2}};
  int instances = 0, optimal = 0;
  for (const auto& shape : shapes)
    for (uint64_t seed = 1; seed <= 8; ++seed) {
      SCOPED_TRACE("S=" + std::to_string(shape.size()) + " seed " + std::to_string(seed));
      // Every tuple of ≥ 2 real indices is listed with probability 0.3, at a cost in [−10, 2].
      TupleListSD p = list_with_singletons(shape, 0.0);
      CounterRng rng(seed, 7, 0);
      const int32_t S = p.dims();
      std::vector<int32_t> t(S, 0);
      std::function<void(int32_t)> each = [&](int32_t s) {
        if (s == S) {
          if (std::count_if(t.begin(), t.end(), [](int32_t i) { return i >= 0; }) >= 2 &&
              rng.uniform(0.0, 1.0) < 0.3)
            add(p, t, rng.uniform(-10.0, 2.0));
          return;
        }
        for (int32_t i = -1; i < p.n[s]; ++i) t[s] = i, each(s + 1);
      };
      each(0);
      const CostTensorSD c = dense_of(p);
      const double optimum = brute_force_sd(c);
      const SolutionSD sol = solve_lagrangian_sd_tuples(p);
      expect_certified_sd(c, sol, optimum);
      optimal += std::abs(sol.summary.objective - optimum) < 1e-4;
      ++instances;
    }
  EXPECT_EQ(instances, 40);
  EXPECT_GE(optimal, 32) << "the relaxation should find most optima of these tiny lists";
}

TEST(LagrangianSDTuples, TwoSensorsIsOneExactLap) {
  // 3 × 3, pairs on the diagonal at −5 and (0, 1), (1, 0) at −6: two crossed pairs and (2, 2) = −17.
  TupleListSD p = list_with_singletons({3, 3}, 0.0);
  for (int32_t i = 0; i < 3; ++i) add(p, {i, i}, -5.0);
  add(p, {0, 1}, -6.0);
  add(p, {1, 0}, -6.0);
  const SolutionSD s = solve_lagrangian_sd_tuples(p);
  EXPECT_DOUBLE_EQ(s.summary.objective, -17.0);
  EXPECT_NEAR(s.summary.lower_bound, -17.0, 1e-9);
  EXPECT_EQ(s.summary.termination, Termination::kOptimal);
}

TEST(LagrangianSDTuples, BadListsAreRejected) {
  TupleListSD p = list_with_singletons({2, 2, 1}, 0.0);
  TupleListSD missing = p;
  missing.tuples.erase(missing.tuples.begin(), missing.tuples.begin() + 3);  // a0's singleton
  missing.cost.erase(missing.cost.begin());
  EXPECT_THROW(solve_lagrangian_sd_tuples(missing), InputError);
  TupleListSD nan = p;
  add(nan, {0, 0, kNoTrack}, std::numeric_limits<double>::quiet_NaN());
  EXPECT_THROW(solve_lagrangian_sd_tuples(nan), InputError);
  TupleListSD range = p;
  add(range, {0, 2, kNoTrack}, -1.0);
  EXPECT_THROW(solve_lagrangian_sd_tuples(range), InputError);
  TupleListSD dummies = p;
  add(dummies, {kNoTrack, kNoTrack, kNoTrack}, -1.0);
  EXPECT_THROW(solve_lagrangian_sd_tuples(dummies), InputError);
}

}  // namespace
}  // namespace trackassoc
