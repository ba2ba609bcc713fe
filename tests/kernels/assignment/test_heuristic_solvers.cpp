// Greedy and sequential pairwise 3-D assignment heuristics: validity, recomputed objective, brute
// force on planted (greedy-friendly) instances, hand examples, unequal sizes and misses.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "kernels/assignment/heuristic_solvers.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cost_tensor.hpp"

namespace trackassoc {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

CostTensor3 random_tensor(int32_t n1, int32_t n2, int32_t n3, uint64_t stream, bool integer_costs = false) {
  CostTensor3 b(n1, n2, n3);
  CounterRng rng(99, stream);
  for (auto& c : b.cost)
    c = integer_costs ? static_cast<float>(rng.uniform_int(20)) : static_cast<float>(rng.uniform(0, 100));
  return b;
}

// Exhaustive optimum of a square n×n×n instance: all pairs of permutations.
double brute_force_optimum(const CostTensor3& b) {
  const int n = b.n1;
  std::vector<int> p(n), q(n);
  std::iota(p.begin(), p.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    std::iota(q.begin(), q.end(), 0);
    do {
      double s = 0.0;
      for (int i = 0; i < n; ++i) s += b.at(i, p[i], q[i]);
      best = std::min(best, s);
    } while (std::next_permutation(q.begin(), q.end()));
  } while (std::next_permutation(p.begin(), p.end()));
  return best;
}

// Checks of a heuristic's answer that do not go through assignment_types.hpp: every index of
// every dimension used at most once (counted here); the objective is the sum, written out here, of
// the tuples' entries, miss_cost per missing index and, with a finite miss_cost, 2·miss_cost per
// index in no tuple; on a square instance of at most 5 per dimension without misses, it is never
// below the brute-force optimum.
void expect_valid_heuristic(const CostTensor3& b, const Solution3& s) {
  EXPECT_TRUE(is_valid_assignment(b, s.tuples));
  EXPECT_TRUE(s.summary.feasible);
  EXPECT_EQ(s.summary.termination, Termination::kHeuristic);
  EXPECT_DOUBLE_EQ(s.summary.objective, assignment_cost(b, s.tuples));
  const std::array<int32_t, 3> n{b.n1, b.n2, b.n3};
  std::array<std::vector<int>, 3> uses{std::vector<int>(n[0]), std::vector<int>(n[1]),
                                       std::vector<int>(n[2])};
  double by_hand = 0.0;
  int misses = 0;
  for (const Tuple3& t : s.tuples) {
    bool complete = true;
    for (int d = 0; d < 3; ++d) {
      if (t[d] < 0) {
        complete = false;
        ++misses;
        continue;
      }
      ASSERT_LT(t[d], n[d]);
      ++uses[d][t[d]];
    }
    by_hand += complete ? static_cast<double>(b.at(t[0], t[1], t[2])) : 0.0;
  }
  int alone = 0;
  for (int d = 0; d < 3; ++d)
    for (int32_t i = 0; i < n[d]; ++i) {
      EXPECT_LE(uses[d][i], 1) << "dimension " << d << " index " << i << " in " << uses[d][i] << " tuples";
      alone += uses[d][i] == 0;
    }
  if (std::isfinite(b.miss_cost)) {
    by_hand += b.miss_cost * static_cast<double>(misses) + 2.0 * b.miss_cost * static_cast<double>(alone);
  } else {
    EXPECT_EQ(misses, 0);
    EXPECT_EQ(static_cast<int32_t>(s.tuples.size()), std::min({b.n1, b.n2, b.n3}));
  }
  EXPECT_NEAR(s.summary.objective, by_hand, 1e-9 * (1.0 + std::abs(by_hand)));
  if (b.n1 == b.n2 && b.n2 == b.n3 && b.n1 <= 5 && std::isinf(b.miss_cost)) {
    EXPECT_GE(s.summary.objective, brute_force_optimum(b) - 1e-9 * (1.0 + std::abs(by_hand)));
  }
}

TEST(Greedy, ValidAndObjectiveRecomputedOnUnequalSizes) {
  for (auto [n1, n2, n3] :
       {std::array{4, 6, 5}, std::array{7, 3, 9}, std::array{8, 8, 2}, std::array{1, 1, 1}}) {
    const CostTensor3 b = random_tensor(n1, n2, n3, n1 * 100 + n2 * 10 + n3);
    const Solution3 s = solve_greedy3(b);
    expect_valid_heuristic(b, s);
    EXPECT_EQ(static_cast<int>(s.tuples.size()), std::min({n1, n2, n3}));
  }
}

// Planted instances: a hidden assignment with costs in [0, 1), every other tuple in [10, 20).
// The planted tuples are the n cheapest and mutually compatible, so greedy must find them, and
// brute force confirms they are optimal.
TEST(Greedy, EqualsBruteForceOnPlantedInstances) {
  const int n = 5;
  for (uint64_t run = 0; run < 6; ++run) {
    CounterRng rng(5, run);
    CostTensor3 b(n, n, n);
    for (auto& c : b.cost) c = static_cast<float>(rng.uniform(10, 20));
    std::vector<int32_t> p(n), q(n);
    std::iota(p.begin(), p.end(), 0);
    std::iota(q.begin(), q.end(), 0);
    rng.shuffle(std::span<int32_t>(p));
    rng.shuffle(std::span<int32_t>(q));
    for (int i = 0; i < n; ++i) b.at(i, p[i], q[i]) = static_cast<float>(rng.uniform(0, 1));
    const Solution3 s = solve_greedy3(b);
    expect_valid_heuristic(b, s);
    EXPECT_NEAR(s.summary.objective, brute_force_optimum(b), 1e-6);
    for (const auto& t : s.tuples) {
      EXPECT_EQ(t[1], p[t[0]]);
      EXPECT_EQ(t[2], q[t[0]]);
    }
  }
}

// Reference greedy: sort everything by (cost, linear index), scan once.
std::vector<Tuple3> naive_greedy(const CostTensor3& b) {
  std::vector<std::size_t> order(b.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return b.cost[x] < b.cost[y]; });
  std::vector<char> u1(b.n1), u2(b.n2), u3(b.n3);
  std::vector<Tuple3> out;
  for (std::size_t p : order) {
    if (!std::isfinite(b.cost[p])) break;
    const int32_t i = p / (b.n2 * b.n3), j = p / b.n3 % b.n2, k = p % b.n3;
    if (u1[i] || u2[j] || u3[k]) continue;
    u1[i] = u2[j] = u3[k] = 1;
    out.push_back({i, j, k});
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Greedy, RoundsMatchTheFullSortGreedyIncludingTies) {
  for (auto [n1, n2, n3] : {std::array{60, 55, 50}, std::array{40, 40, 40}}) {
    const CostTensor3 b = random_tensor(n1, n2, n3, 7 + n1, /*integer_costs=*/true);  // many ties
    const Solution3 s = solve_greedy3(b);
    EXPECT_EQ(s.tuples, naive_greedy(b));
    EXPECT_GT(s.summary.iterations, 0);
  }
}

// n = 2, hand example where greedy is trapped and pairwise is not:
//   b000 = 0, b111 = 100, b011 = b100 = 10, every other entry 50.
//   greedy takes (0,0,0) first and must then take (1,1,1): 100.
//   pairwise: c12 = min_k b = [[0, 10], [10, 50]]; LAP picks (0,1),(1,0) at 20;
//   then pair (0,1) takes k=1 (10) and pair (1,0) takes k=0 (10): 20, the optimum.
CostTensor3 trap_instance() {
  CostTensor3 b(2, 2, 2, 50.f);
  b.at(0, 0, 0) = 0.f;
  b.at(1, 1, 1) = 100.f;
  b.at(0, 1, 1) = 10.f;
  b.at(1, 0, 0) = 10.f;
  return b;
}

TEST(Greedy, HandExampleTrapped) {
  const CostTensor3 b = trap_instance();
  const Solution3 s = solve_greedy3(b);
  expect_valid_heuristic(b, s);
  EXPECT_DOUBLE_EQ(s.summary.objective, 100.0);
  EXPECT_EQ(brute_force_optimum(b), 20.0);
}

TEST(Pairwise, HandExampleFindsOptimum) {
  const CostTensor3 b = trap_instance();
  const Solution3 s = solve_pairwise3(b);
  expect_valid_heuristic(b, s);
  EXPECT_DOUBLE_EQ(s.summary.objective, 20.0);
  EXPECT_EQ(s.tuples, (std::vector<Tuple3>{{0, 1, 1}, {1, 0, 0}}));
}

TEST(Pairwise, ValidAndObjectiveRecomputedOnUnequalSizes) {
  for (auto [n1, n2, n3] :
       {std::array{4, 6, 5}, std::array{6, 3, 5}, std::array{5, 5, 2}, std::array{1, 1, 1}}) {
    const CostTensor3 b = random_tensor(n1, n2, n3, 1000 + n1 * 100 + n2 * 10 + n3);
    const Solution3 s = solve_pairwise3(b);
    expect_valid_heuristic(b, s);
    EXPECT_EQ(static_cast<int>(s.tuples.size()), std::min({n1, n2, n3}));
  }
}

TEST(Pairwise, EqualsBruteForceOnPlantedInstances) {
  const int n = 5;
  for (uint64_t run = 0; run < 4; ++run) {
    CounterRng rng(6, run);
    CostTensor3 b(n, n, n);
    for (auto& c : b.cost) c = static_cast<float>(rng.uniform(10, 20));
    std::vector<int32_t> p(n), q(n);
    std::iota(p.begin(), p.end(), 0);
    std::iota(q.begin(), q.end(), 0);
    rng.shuffle(std::span<int32_t>(p));
    rng.shuffle(std::span<int32_t>(q));
    for (int i = 0; i < n; ++i) b.at(i, p[i], q[i]) = static_cast<float>(rng.uniform(0, 1));
    const Solution3 s = solve_pairwise3(b);
    expect_valid_heuristic(b, s);
    EXPECT_NEAR(s.summary.objective, brute_force_optimum(b), 1e-6);
  }
}

// Finite miss cost m = 1: an index alone costs 2m, so greedy takes a tuple only below 6m = 6.
//   b000 = 2 (taken), b111 = 7 (left: its three singletons cost 6), everything else 10.
TEST(Heuristics, FiniteMissCostLeavesExpensiveIndicesUnassigned) {
  CostTensor3 b(2, 2, 2, 10.f);
  b.at(0, 0, 0) = 2.f;
  b.at(1, 1, 1) = 7.f;
  b.miss_cost = 1.f;
  for (const Solution3& s : {solve_greedy3(b), solve_pairwise3(b)}) {
    expect_valid_heuristic(b, s);
    EXPECT_EQ(s.tuples, (std::vector<Tuple3>{{0, 0, 0}}));
    EXPECT_DOUBLE_EQ(s.summary.objective, 2.0 + 3 * 2.0);  // b000 + three indices alone at 2m
    EXPECT_NE(s.summary.message.find("3 indices alone"), std::string::npos) << s.summary.message;
  }
}

TEST(Heuristics, ForbiddenEntriesReportInfeasible) {
  CostTensor3 b(2, 2, 2, kInf);
  b.at(0, 0, 0) = 1.f;  // only one complete tuple has a finite cost; two are needed
  for (const Solution3& s : {solve_greedy3(b), solve_pairwise3(b)}) {
    EXPECT_FALSE(s.summary.feasible);
    EXPECT_EQ(s.summary.termination, Termination::kInfeasible);
    EXPECT_DOUBLE_EQ(s.summary.objective, assignment_cost(b, s.tuples));
    for (const auto& t : s.tuples) EXPECT_TRUE(std::isfinite(b.at(t[0], t[1], t[2])));
  }
  EXPECT_EQ(solve_greedy3(b).tuples, (std::vector<Tuple3>{{0, 0, 0}}));
}

TEST(Heuristics, EmptyDimensionAndBadInput) {
  const CostTensor3 empty(0, 3, 4);
  for (const Solution3& s : {solve_greedy3(empty), solve_pairwise3(empty)}) {
    EXPECT_TRUE(s.tuples.empty());
    EXPECT_TRUE(s.summary.feasible);
    EXPECT_EQ(s.summary.objective, 0.0);
  }
  CostTensor3 nan(2, 2, 2, 1.f);
  nan.at(1, 0, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(solve_greedy3(nan), InputError);
  EXPECT_THROW(solve_pairwise3(nan), InputError);
  CostTensor3 bad_size(2, 2, 2, 1.f);
  bad_size.cost.pop_back();
  EXPECT_THROW(solve_greedy3(bad_size), InputError);
  CostTensor3 neg_miss(2, 2, 2, 1.f);
  neg_miss.miss_cost = -1.f;
  EXPECT_THROW(solve_pairwise3(neg_miss), InputError);
}

// The association kernels together: 3 asynchronous sensors see 8 well-separated targets (1 km
// apart, 20 m position noise), with shuffled local track numbers; alignment → statistic → chain
// tensor → greedy / pairwise must pair the tracks of the same target.
TEST(Heuristics, EndToEndThreeSensorsRecoverTruth) {
  const int n = 8;
  TrackTable tt(StateLayout::kXY_VXVY);
  CounterRng rng(31, 0, 0);
  for (int s = 0; s < 3; ++s) {
    std::vector<int32_t> number(n);
    std::iota(number.begin(), number.end(), 100 * s);
    rng.shuffle(std::span<int32_t>(number));
    for (int target = 0; target < n; ++target)
      for (int scan = 0; scan <= 12; ++scan) {
        const double t = scan + 0.3 * s;
        const Eigen::Vector4d truth(1000.0 * target + 100.0 * t, 50.0 * t, 100.0, 50.0);
        Eigen::Vector4d x = truth;
        for (int c = 0; c < 4; ++c) x[c] += (c < 2 ? 20.0 : 2.0) * rng.normal();
        const Eigen::MatrixXd P = Eigen::Vector4d(400.0, 400.0, 4.0, 4.0).asDiagonal();
        tt.push_back(s, number[target], t, x, P, target);
      }
  }
  std::vector<double> times;
  for (int k = 1; k <= 10; ++k) times.push_back(k + 0.7);
  std::array<AlignedTracks, 3> al;
  for (int s = 0; s < 3; ++s) al[s] = align_tracks(tt, s, times, AlignmentOptions{});
  const PairStatistic s12 = independent_sequential_statistic(al[0], al[1], StatisticOptions{});
  const PairStatistic s23 = independent_sequential_statistic(al[1], al[2], StatisticOptions{});
  int true_in_gate = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (al[0].truth[i] == al[1].truth[j]) true_in_gate += s12.in_gate[i * n + j];
  EXPECT_GE(true_in_gate, n - 1);  // gate probability 0.99
  const CostTensor3 b = build_cost_tensor(s12, s23, nullptr, CostTensorOptions{});
  for (const Solution3& sol : {solve_greedy3(b), solve_pairwise3(b)}) {
    expect_valid_heuristic(b, sol);
    ASSERT_EQ(sol.tuples.size(), static_cast<std::size_t>(n));
    for (const auto& t : sol.tuples) {
      EXPECT_EQ(al[0].truth[t[0]], al[1].truth[t[1]]);
      EXPECT_EQ(al[1].truth[t[1]], al[2].truth[t[2]]);
    }
  }
}

}  // namespace
}  // namespace trackassoc
