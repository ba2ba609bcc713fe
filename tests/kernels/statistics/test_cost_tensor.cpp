// The dense cost tensor (seed 000 Eq. 3) against a naive triple loop, the gate substitution, the
// memory-budget refusal and 1 vs 2 threads.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/cost_tensor.hpp"

namespace trackassoc {
namespace {

PairStatistic random_statistic(int32_t na, int32_t nb, uint64_t stream, double gate_fraction) {
  CounterRng rng(2024, stream);
  PairStatistic s;
  s.n_a = na;
  s.n_b = nb;
  for (int64_t p = 0; p < int64_t{na} * nb; ++p) {
    s.lambda.push_back(rng.uniform(0.0, 50.0));
    s.dof.push_back(8);
    s.in_gate.push_back(rng.uniform() < gate_fraction ? 1 : 0);
  }
  return s;
}

double pair_cost(const PairStatistic& s, int a, int b, double gated) {
  const std::size_t p = static_cast<std::size_t>(a) * s.n_b + b;
  return s.in_gate[p] ? s.lambda[p] : gated;
}

// Naive reference in double: b_ijk = λ_ij + λ_jk (+ λ_ik), gated pairs replaced.
void expect_matches_naive(const CostTensor3& b, const PairStatistic& s12, const PairStatistic& s23,
                          const PairStatistic* s13, double gated) {
  ASSERT_EQ(b.n1, s12.n_a);
  ASSERT_EQ(b.n2, s12.n_b);
  ASSERT_EQ(b.n3, s23.n_b);
  ASSERT_EQ(b.size(), static_cast<std::size_t>(b.n1) * b.n2 * b.n3);
  for (int i = 0; i < b.n1; ++i)
    for (int j = 0; j < b.n2; ++j)
      for (int k = 0; k < b.n3; ++k) {
        double want = pair_cost(s12, i, j, gated) + pair_cost(s23, j, k, gated);
        if (s13) want += pair_cost(*s13, i, k, gated);
        ASSERT_NEAR(b.at(i, j, k), want, 1e-6 * std::max(1.0, want)) << i << "," << j << "," << k;
      }
}

TEST(CostTensor, ChainFormMatchesNaiveTripleLoop) {
  const PairStatistic s12 = random_statistic(13, 17, 1, 0.7), s23 = random_statistic(17, 11, 2, 0.7);
  CostTensorOptions opt;
  opt.form = CostForm::kChain;
  opt.gated_pair_cost = 500.0;
  expect_matches_naive(build_cost_tensor(s12, s23, nullptr, opt), s12, s23, nullptr, 500.0);
}

TEST(CostTensor, AllPairsFormMatchesNaiveTripleLoop) {
  const PairStatistic s12 = random_statistic(9, 14, 3, 0.6), s23 = random_statistic(14, 21, 4, 0.6),
                      s13 = random_statistic(9, 21, 5, 0.6);
  CostTensorOptions opt;
  opt.form = CostForm::kAllPairs;
  opt.gated_pair_cost = 123.5;
  expect_matches_naive(build_cost_tensor(s12, s23, &s13, opt), s12, s23, &s13, 123.5);
}

TEST(CostTensor, AutomaticGatedCostIsTenTimesLargestInGateLambda) {
  PairStatistic s12{1, 2, {3.0, 7000.0}, {4, 4}, {1, 0}};  // the gated 7000 does not count
  PairStatistic s23{2, 1, {150.0, 2.0}, {4, 4}, {1, 1}};
  const CostTensor3 b = build_cost_tensor(s12, s23, nullptr, CostTensorOptions{});
  // max in-gate λ = 150 → gated cost 1500 (≥ 1e3).
  EXPECT_FLOAT_EQ(b.at(0, 0, 0), 3.0f + 150.0f);
  EXPECT_FLOAT_EQ(b.at(0, 1, 0), 1500.0f + 2.0f);
  s23.lambda[0] = 20.0;  // max in-gate 20 → 200, floored at 1e3
  EXPECT_FLOAT_EQ(build_cost_tensor(s12, s23, nullptr, CostTensorOptions{}).at(0, 1, 0), 1000.0f + 2.0f);
  EXPECT_TRUE(std::isinf(b.miss_cost));
}

TEST(CostTensor, ReusesStorageAndResizes) {
  const PairStatistic s12 = random_statistic(5, 6, 6, 0.5), s23 = random_statistic(6, 7, 7, 0.5);
  CostTensor3 b(5, 6, 7, -1.f);
  const float* before = b.cost.data();
  build_cost_tensor_into(s12, s23, nullptr, CostTensorOptions{}, b);
  EXPECT_EQ(b.cost.data(), before);
  const CostTensor3 fresh = build_cost_tensor(s12, s23, nullptr, CostTensorOptions{});
  EXPECT_EQ(b.cost, fresh.cost);
  CostTensor3 small(1, 1, 1);
  build_cost_tensor_into(s12, s23, nullptr, CostTensorOptions{}, small);
  EXPECT_EQ(small.cost, fresh.cost);
}

TEST(CostTensor, RefusesOverBudgetNamingSizeBudgetAndSparseForm) {
  const PairStatistic s12 = random_statistic(20, 30, 8, 0.5), s23 = random_statistic(30, 40, 9, 0.5);
  CostTensorOptions opt;
  opt.memory_budget_bytes = 20 * 30 * 40 * 4 - 1;  // one byte short of 96000
  try {
    build_cost_tensor(s12, s23, nullptr, opt);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("20x30x40"), std::string::npos) << msg;
    EXPECT_NE(msg.find("96000 bytes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("95999"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sparse"), std::string::npos) << msg;
  }
  opt.memory_budget_bytes = 20 * 30 * 40 * 4;  // exactly enough
  EXPECT_NO_THROW(build_cost_tensor(s12, s23, nullptr, opt));
  // n = 1500 per sensor with the default 2 GiB budget: 13.5 GB refused before any allocation.
  const std::size_t m = 1500 * 1500;
  const PairStatistic x{1500, 1500, std::vector<double>(m, 1.0), std::vector<int32_t>(m, 4),
                        std::vector<uint8_t>(m, 1)};
  EXPECT_THROW(build_cost_tensor(x, x, nullptr, CostTensorOptions{}), InputError);
}

TEST(CostTensor, BadInputRaisesInputError) {
  const PairStatistic s12 = random_statistic(3, 4, 10, 0.5), s23 = random_statistic(5, 2, 11, 0.5);
  EXPECT_THROW(build_cost_tensor(s12, s23, nullptr, CostTensorOptions{}), InputError);  // 4 ≠ 5
  const PairStatistic ok23 = random_statistic(4, 2, 12, 0.5);
  CostTensorOptions all;
  all.form = CostForm::kAllPairs;
  EXPECT_THROW(build_cost_tensor(s12, ok23, nullptr, all), InputError);  // s13 missing
  const PairStatistic bad13 = random_statistic(3, 3, 13, 0.5);
  EXPECT_THROW(build_cost_tensor(s12, ok23, &bad13, all), InputError);  // 3x3 ≠ 3x2
  PairStatistic nan12 = s12;
  nan12.lambda[5] = std::nan("");
  nan12.in_gate[5] = 0;
  EXPECT_NO_THROW(build_cost_tensor(nan12, ok23, nullptr, CostTensorOptions{}));  // gated out: unused
  nan12.in_gate[5] = 1;
  EXPECT_THROW(build_cost_tensor(nan12, ok23, nullptr, CostTensorOptions{}), InputError);
  CostTensorOptions neg;
  neg.gated_pair_cost = -1.0;
  EXPECT_THROW(neg.validate(), InputError);
  // Empty dimensions give an empty tensor.
  const PairStatistic e12 = random_statistic(0, 4, 14, 0.5);
  const CostTensor3 empty = build_cost_tensor(e12, ok23, nullptr, CostTensorOptions{});
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.n2, 4);
}

TEST(CostTensor, OneAndTwoThreadsBitIdentical) {
  const PairStatistic s12 = random_statistic(64, 60, 15, 0.8), s23 = random_statistic(60, 70, 16, 0.8),
                      s13 = random_statistic(64, 70, 17, 0.8);
  for (CostForm form : {CostForm::kChain, CostForm::kAllPairs}) {
    CostTensorOptions opt;
    opt.form = form;
    CostTensor3 b1, b2;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
      b1 = build_cost_tensor(s12, s23, &s13, opt);
    }
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
      b2 = build_cost_tensor(s12, s23, &s13, opt);
    }
    ASSERT_EQ(b1.size(), b2.size());
    EXPECT_EQ(0, std::memcmp(b1.cost.data(), b2.cost.data(), b1.size() * sizeof(float)));
  }
}

}  // namespace
}  // namespace trackassoc
