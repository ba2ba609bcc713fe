// Clique relax-and-cut (kernels/assignment/clique_cuts.hpp): the clique Q(r) and its load against a
// direct "shares two indices" count, validity of Σ_{Q(r)} x ≤ 1 on every assignment (enumerated),
// and the honesty of the bound: never above the optimum (brute force on small random and
// tracking-like instances; the known optima of Balas–Saltzman and the small DecompLib sets), and
// reproduced independently from the multipliers it returns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/clique_cuts.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "tests/support/hopfield_instances.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;

bool in_clique(const Tuple3& r, const Tuple3& s) {
  return (r[0] == s[0]) + (r[1] == s[1]) + (r[2] == s[2]) >= 2;
}

TEST(CliqueCuts, PenaltyCoversExactlyTheTuplesSharingTwoIndices) {
  const CostTensor3 b(4, 5, 6);
  for (const Tuple3& r : {Tuple3{0, 0, 0}, Tuple3{2, 3, 5}, Tuple3{3, 4, 1}}) {
    std::vector<double> w(b.size(), 0.0);
    add_clique_penalty(b, r, 0.5, w);
    int members = 0;
    for (int32_t i = 0; i < b.n1; ++i)
      for (int32_t j = 0; j < b.n2; ++j)
        for (int32_t k = 0; k < b.n3; ++k) {
          const bool member = in_clique(r, {i, j, k});
          EXPECT_EQ(w[b.index(i, j, k)], member ? 0.5 : 0.0) << i << j << k;
          members += member;
        }
    EXPECT_EQ(members, b.n1 + b.n2 + b.n3 - 2);  // r, and n_d − 1 along each dimension
  }
}

// Every assignment of a 4×4×4 cube (4!² = 576): the load of each of the 64 cliques equals the
// direct count of its members in the assignment, and never exceeds 1 (the cut is valid).
TEST(CliqueCuts, LoadMatchesDirectCountAndNeverExceedsOneOnEveryAssignment) {
  const int n = 4;
  std::vector<int32_t> pj(n), pk(n);
  std::iota(pj.begin(), pj.end(), 0);
  int assignments = 0, max_load = 0;
  do {
    std::iota(pk.begin(), pk.end(), 0);
    do {
      std::vector<int32_t> owner(n);
      for (int i = 0; i < n; ++i) owner[pj[i]] = i;
      for (int32_t a = 0; a < n; ++a)
        for (int32_t c = 0; c < n; ++c)
          for (int32_t d = 0; d < n; ++d) {
            const Tuple3 r{a, c, d};
            int direct = 0;
            for (int i = 0; i < n; ++i) direct += in_clique(r, {i, pj[i], pk[i]});
            ASSERT_EQ(clique_load(r, pj, pk, owner), direct);
            max_load = std::max(max_load, direct);
          }
      ++assignments;
    } while (std::next_permutation(pk.begin(), pk.end()));
  } while (std::next_permutation(pj.begin(), pj.end()));
  EXPECT_EQ(assignments, 576);
  EXPECT_EQ(max_load, 1);
}

// Load of a relaxed solution (k may repeat): two rows sharing a k load the two cliques the
// separation names with 2, a lone row's own tuple with 1.
TEST(CliqueCuts, LoadOfARelaxedSolutionWithARepeatedK) {
  const std::vector<int32_t> row_j{0, 1, 2}, row_k{1, 1, 0}, owner{0, 1, 2};
  EXPECT_EQ(clique_load({0, 1, 1}, row_j, row_k, owner), 2);  // (i1, j2, k)
  EXPECT_EQ(clique_load({1, 0, 1}, row_j, row_k, owner), 2);  // (i2, j1, k)
  EXPECT_EQ(clique_load({2, 2, 0}, row_j, row_k, owner), 1);
  EXPECT_EQ(clique_load({2, 0, 2}, row_j, row_k, owner), 0);
}

// L(μ, λ) recomputed from scratch from the returned roots, λ and μ: w by the direct membership
// test, c_ij = min_k w_ijk + μ_k, our LAP, minus Σμ and Σλ.
double independent_bound(const CostTensor3& b, const CliqueRelaxation& r) {
  std::vector<double> c(static_cast<std::size_t>(b.n1) * b.n2);
  for (int32_t i = 0; i < b.n1; ++i)
    for (int32_t j = 0; j < b.n2; ++j) {
      double best = std::numeric_limits<double>::infinity();
      for (int32_t k = 0; k < b.n3; ++k) {
        double w = b.at(i, j, k);
        for (std::size_t q = 0; q < r.roots.size(); ++q)
          if (in_clique(r.roots[q], {i, j, k})) w += r.lambda[q];
        best = std::min(best, w + r.mu[k]);
      }
      c[static_cast<std::size_t>(i) * b.n2 + j] = best;
    }
  double bound = solve_lap(c, b.n1, b.n2).cost;
  for (double m : r.mu) bound -= m;
  for (double l : r.lambda) bound -= l;
  return bound;
}

CliqueRelaxation root_with_cuts(const CanonicalProblem3& p, LagrangianRun* plain = nullptr) {
  LagrangianOptions lo;
  lo.local_search = true;
  const auto t0 = std::chrono::steady_clock::now();
  const LagrangianRun run = run_lagrangian(p, lo);
  if (plain) *plain = run;
  return run_clique_relaxation(p, lo, CliqueCutOptions{}, run, t0);
}

void expect_honest(const CostTensor3& b, double optimum, const std::string& name, int* lifted) {
  SCOPED_TRACE(name);
  const CanonicalProblem3 p = make_canonical(b);
  LagrangianRun plain;
  const CliqueRelaxation r = root_with_cuts(p, &plain);
  EXPECT_LE(r.lower_bound, optimum + 1e-9);
  EXPECT_GE(r.upper_bound, optimum - 1e-9);
  EXPECT_DOUBLE_EQ(tuples_cost(p.tensor, r.best_tuples), r.upper_bound);
  ASSERT_EQ(r.lambda.size(), r.roots.size());
  for (double l : r.lambda) EXPECT_GE(l, 0.0);
  const double again = independent_bound(p.tensor, r);
  EXPECT_LE(again, optimum + 1e-6);
  if (r.lower_bound > plain.lower_bound) {
    // The returned multipliers are those of the reported bound.
    const double rounded = p.integer_costs ? std::ceil(again - 1e-6) : again;
    EXPECT_NEAR(rounded, r.lower_bound, 1e-6);
    ++*lifted;
  }
  std::vector<double> w(p.tensor.cost.begin(), p.tensor.cost.end());
  for (std::size_t q = 0; q < r.roots.size(); ++q) add_clique_penalty(p.tensor, r.roots[q], r.lambda[q], w);
  ASSERT_EQ(w.size(), r.penalised.size());
  for (std::size_t e = 0; e < w.size(); ++e) ASSERT_NEAR(w[e], r.penalised[e], 1e-9);
}

// Random integer cubes n = 5, 6 (brute force), where the plain LP bound often falls short.
TEST(CliqueCuts, BoundNeverAboveBruteForceOptimumOnRandomCubes) {
  CounterRng rng(18, 1);
  int lifted = 0;
  for (int t = 0; t < 24; ++t) {
    const int n = t % 2 ? 6 : 5;
    CostTensor3 b(n, n, n);
    for (auto& x : b.cost) x = static_cast<float>(rng.uniform_int(30));
    expect_honest(b, brute_force_optimum(b), "random " + std::to_string(t), &lifted);
  }
  EXPECT_GT(lifted, 0);  // the cuts did lift the bound on some of them
}

// Tracking-like chain costs (tests/support/hopfield_instances.hpp), dense enough that greedy errs;
// non-integer costs, and a rectangular case (n1 < n3, μ ≥ 0).
TEST(CliqueCuts, BoundNeverAboveBruteForceOptimumOnTrackingInstances) {
  int lifted = 0;
  for (int t = 0; t < 12; ++t) {
    GeometricInstanceOptions o;
    o.n = 5 + t % 2;
    o.noise_to_spacing = 1.0;
    const GeometricInstance g = make_geometric_instance(o, 18, static_cast<uint64_t>(t));
    expect_honest(g.cost, brute_force_optimum(g.cost), "tracking " + std::to_string(t), &lifted);
  }
  CounterRng rng(18, 2);
  for (int t = 0; t < 6; ++t) {
    CostTensor3 b(4, 5, 6);
    for (auto& x : b.cost) x = static_cast<float>(rng.uniform(0.0, 10.0));
    expect_honest(b, brute_force_optimum(b), "rectangular " + std::to_string(t), &lifted);
  }
}

int check_balas_saltzman(int n_from, int n_to) {
  const auto optima = read_known_optima(balas_saltzman("bs.opt"));
  int lifted = 0, checked = 0;
  for (int n = n_from; n <= n_to; n += 2)
    for (int r = 1; r <= 5; ++r) {
      const std::string name = "bs." + std::to_string(n) + "." + std::to_string(r);
      expect_honest(read_3dap_instance(balas_saltzman(name + ".txt")), optima.at(name), name, &lifted);
      ++checked;
    }
  return checked;
}

TEST(CliqueCuts, BoundNeverAboveKnownOptimumOnBalasSaltzmanUpTo16) {
  EXPECT_EQ(check_balas_saltzman(4, 16), 35);
}
TEST(CliqueCuts, BoundNeverAboveKnownOptimumOnBalasSaltzman18To26) {
  EXPECT_EQ(check_balas_saltzman(18, 26), 25);
}

TEST(CliqueCuts, BoundNeverAboveKnownOptimumOnSmallDecompLib) {
  const auto optima = read_known_optima(decomplib("ap3.opt"));
  int lifted = 0, checked = 0;
  for (int n : {5, 10, 20})
    for (int r = 1; r <= 10; ++r) {
      const std::string name = "ap3." + std::to_string(n) + "." + std::to_string(r);
      expect_honest(read_3dap_instance(decomplib(name + ".txt")), optima.at(name), name, &lifted);
      ++checked;
    }
  EXPECT_EQ(checked, 30);
  EXPECT_GT(lifted, 0);
}

TEST(CliqueCuts, OptionsAreValidated) {
  CliqueCutOptions o;
  o.iterations_per_round = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.theta = 2.5;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.max_rounds = -1;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace trackassoc
