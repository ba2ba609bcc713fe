// The shared decoding of solver tuples (engine/pipeline/tuple_decoding.hpp) on hand-made gates (the dense
// and sparse pipelines on unequal counts: tests/engine/pipeline/test_sparse_pipeline.cpp).
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <vector>

#include "engine/pipeline/tuple_decoding.hpp"

namespace trackassoc {
namespace {

constexpr double kOut = std::numeric_limits<double>::quiet_NaN();

// A gate given as a table {(q, a, b) → λ}; everything else is outside.
struct TableGate {
  std::map<std::array<int32_t, 3>, double> in;
  GatedLambda lambda() const {
    return [this](int q, int32_t a, int32_t b) {
      const auto it = in.find({q, a, b});
      return it == in.end() ? kOut : it->second;
    };
  }
};

struct Out {
  std::vector<std::pair<std::array<int32_t, 3>, double>> tuples;
  EmitTuple emit() {
    return [this](const std::array<int32_t, 3>& t, double c) { tuples.push_back({t, c}); };
  }
};

constexpr int32_t X = kNoTrack;

TEST(TupleDecoding, TupleInsideTheGateIsKeptWhole) {
  TableGate g;
  g.in = {{{0, 1, 2}, 3.0}, {{1, 2, 5}, 4.0}};  // 1–2 and 2–3 in; 1–3 out
  Out out;
  std::array<std::vector<int32_t>, 3> left;
  split_tuple(
      g.lambda(), {1, 2, 5}, false, [](double a, double b, double) { return a + b; }, out.emit(), left);
  ASSERT_EQ(out.tuples.size(), 1u);
  EXPECT_TRUE(left[0].empty() && left[1].empty() && left[2].empty());
  EXPECT_EQ(out.tuples[0].first, (std::array<int32_t, 3>{1, 2, 5}));
  EXPECT_EQ(out.tuples[0].second, 7.0);
  // The all-pairs form also needs 1–3: now the tuple splits into its best pair (λ12 = 3 < λ23 = 4).
  Out split;
  split_tuple(
      g.lambda(), {1, 2, 5}, true, [](double, double, double) { return 0.0; }, split.emit(), left);
  ASSERT_EQ(split.tuples.size(), 1u);
  EXPECT_EQ(split.tuples[0].first, (std::array<int32_t, 3>{1, 2, X}));
  EXPECT_EQ(split.tuples[0].second, 3.0);
  EXPECT_EQ(left, (std::array<std::vector<int32_t>, 3>{{{}, {}, {5}}}));
}

TEST(TupleDecoding, OutOfGateTupleKeepsItsBestPairAndDummiesAreSkipped) {
  TableGate g;
  g.in = {{{1, 2, 5}, 4.0}, {{2, 1, 5}, 1.5}};  // 2–3 and 1–3 in, 1–2 out
  Out out;
  std::array<std::vector<int32_t>, 3> left;
  split_tuple(
      g.lambda(), {1, 2, 5}, false, [](double, double, double) { return -1.0; }, out.emit(), left);
  ASSERT_EQ(out.tuples.size(), 1u);
  EXPECT_EQ(out.tuples[0].first, (std::array<int32_t, 3>{1, X, 5}));  // λ13 = 1.5 is the best pair
  EXPECT_EQ(out.tuples[0].second, 1.5);
  EXPECT_EQ(left, (std::array<std::vector<int32_t>, 3>{{{}, {2}, {}}}));
  // A solver tuple with a dummy index (finite miss cost) and no gated pair: both tracks left over.
  Out dummy;
  split_tuple(
      g.lambda(), {7, X, 9}, false, [](double, double, double) { return -1.0; }, dummy.emit(), left);
  EXPECT_TRUE(dummy.tuples.empty());
  EXPECT_EQ(left, (std::array<std::vector<int32_t>, 3>{{{7}, {2}, {9}}}));
}

// Leftovers 1: {0, 1}, 2: {4}, 3: {8, 9}. Gated pairs by λ: (2:4, 3:9) 0.5, (1:0, 2:4) 1.0,
// (1:1, 3:8) 2.0, (1:0, 3:9) 3.0. Greedy: (4, 9) first; (0, 4) is then taken by 4; (1, 8);
// (0, 9) is taken by 9; 1:0 stays alone.
TEST(TupleDecoding, LeftoversArePairedGreedilyByGatedLambda) {
  TableGate g;
  g.in = {{{1, 4, 9}, 0.5}, {{0, 0, 4}, 1.0}, {{2, 1, 8}, 2.0}, {{2, 0, 9}, 3.0}};
  Out out;
  pair_leftovers(g.lambda(), {std::vector<int32_t>{0, 1}, {4}, {8, 9}}, out.emit());
  const std::vector<std::pair<std::array<int32_t, 3>, double>> expected{
      {{X, 4, 9}, 0.5}, {{1, X, 8}, 2.0}, {{0, X, X}, 0.0}};
  EXPECT_EQ(out.tuples, expected);
}

}  // namespace
}  // namespace trackassoc
