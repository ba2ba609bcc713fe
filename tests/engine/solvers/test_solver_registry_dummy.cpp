// The dummy index in every 3-D solver of the registry (issue 6 item 3): with a finite miss_cost,
// every solver returns a valid assignment whose recomputed cost is its objective and is never
// below the brute-force optimum, and the exact solvers reach that optimum.
#include <gtest/gtest.h>

#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/random.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;

TEST(SolverRegistryDummy, EverySolverHandlesAFiniteMissCost) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    CostTensor3 b(3, 4, 3);
    CounterRng rng(seed, 9, 0);
    for (float& v : b.cost) v = static_cast<float>(rng.uniform(0.0, 12.0));
    b.miss_cost = 3.0f;  // some indices are better left without a partner
    const double optimum = brute_force_optimum(b);
    for (const SolverEntry& e : solver_registry()) {
      SCOPED_TRACE(e.name + " seed " + std::to_string(seed));
      const Solution3 s = e.solve(b, nlohmann::json::object(), seed);
      expect_consistent(b, s);
      EXPECT_GE(s.summary.objective, optimum - 1e-4);
      if (e.name == "exact" || e.name == "lr+ls") {
        EXPECT_NEAR(s.summary.objective, optimum, 1e-4);
      }
    }
  }
}

}  // namespace
}  // namespace trackassoc
