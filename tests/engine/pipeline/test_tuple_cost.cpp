// The one S-D tuple cost rule (engine/pipeline/tuple_cost.hpp), on hand-made link costs: the sum of
// the linked pairs' costs; +inf for a coexisting pair outside the gate or members not connected
// through gated pairs; a pair that never coexists neither forbids nor links.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/tuple_cost.hpp"

namespace trackassoc {
namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();  // not a gated pair

// Members 0, 1, 2 with link[x][y] (x < y) and coexist[x][y].
double cost3(const double (&link)[3][3], const bool (&coexist)[3][3], bool all_pairs) {
  return sd_tuple_cost(
      3, all_pairs, [&](std::size_t x, std::size_t y) { return link[x][y]; },
      [&](std::size_t x, std::size_t y) { return coexist[x][y]; });
}

TEST(TupleCost, SumsTheLinkedPairsOfItsForm) {
  const double link[3][3] = {{0, -2.0, -4.0}, {0, 0, -3.0}, {0, 0, 0}};
  const bool together[3][3] = {{false, true, true}, {false, false, true}, {false, false, false}};
  EXPECT_DOUBLE_EQ(cost3(link, together, true), -9.0);   // -2 - 3 - 4
  EXPECT_DOUBLE_EQ(cost3(link, together, false), -5.0);  // chain: -2 - 3
  EXPECT_DOUBLE_EQ(sd_tuple_cost(
                       1, true, [](std::size_t, std::size_t) { return kNone; },
                       [](std::size_t, std::size_t) { return true; }),
                   0.0);  // one track
}

TEST(TupleCost, NeverCoexistingPairIsNeutralACoexistingOneOutsideTheGateForbids) {
  // A early, B throughout, C late: A–C never coexist and have no gated pair.
  const double link[3][3] = {{0, -2.0, kNone}, {0, 0, -3.0}, {0, 0, 0}};
  bool together[3][3] = {{false, true, false}, {false, false, true}, {false, false, false}};
  EXPECT_DOUBLE_EQ(cost3(link, together, true), -5.0);  // joined through B
  together[0][2] = true;                                // A–C coexist and fail the gate
  EXPECT_TRUE(std::isinf(cost3(link, together, true)));
}

TEST(TupleCost, MembersNotConnectedThroughGatedPairsAreForbidden) {
  const double link[3][3] = {{0, -2.0, kNone}, {0, 0, kNone}, {0, 0, 0}};
  const bool apart[3][3] = {};  // C never coexists with A or B: C is not connected
  EXPECT_TRUE(std::isinf(cost3(link, apart, true)));
}

// The rule for one pair, shared with the segment pass (track_segments.cpp): a gated pair's link
// cost (without asking whether the two coexist), +inf for a tested pair outside the gate, NaN for a
// pair that never coexists.
TEST(TupleCost, OnePairsTermIsItsLinkForbiddenOrNoEvidence) {
  int asked = 0;
  const double link = -2.5;
  EXPECT_EQ(sd_pair_term(&link, [&] { return ++asked, true; }), -2.5);
  EXPECT_EQ(asked, 0);
  EXPECT_EQ(sd_pair_term(nullptr, [&] { return ++asked, true; }), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(sd_pair_term(nullptr, [&] { return ++asked, false; })));
  EXPECT_EQ(asked, 2);
}

TEST(TupleCost, ADoubtfulPairAddsItsCostAndLinksNothing) {
  // The family-wise veto's doubtful pair (tagged entry): 0-1 gated at -3, 1-2 gated at -2, 0-2
  // doubtful at +1.5: allowed, -3 - 2 + 1.5 = -3.5 with all pairs; the chain form counts 0-1 and
  // 1-2 only (-5).
  const bool all[3][3] = {{false, true, true}, {false, false, true}, {false, false, false}};
  const double doubtful[3][3] = {{kNone, -3.0, doubtful_pair_entry(1.5)}, {kNone, kNone, -2.0}, {}};
  EXPECT_DOUBLE_EQ(cost3(doubtful, all, true), -3.5);
  EXPECT_DOUBLE_EQ(cost3(doubtful, all, false), -5.0);
  // A doubtful pair does not connect: 0-1 gated, 0-2 doubtful, 1-2 never together: 2 is linked to
  // no member through a gated pair, so the tuple is forbidden.
  const bool apart[3][3] = {{false, true, true}, {false, false, false}, {false, false, false}};
  const double only[3][3] = {{kNone, -3.0, doubtful_pair_entry(1.5)}, {kNone, kNone, kNone}, {}};
  EXPECT_TRUE(std::isinf(cost3(only, apart, true)));
  // Without the tag the same coexisting pair outside the gate forbids the tuple.
  const double vetoed[3][3] = {{kNone, -3.0, kNone}, {kNone, kNone, -2.0}, {}};
  EXPECT_TRUE(std::isinf(cost3(vetoed, all, true)));
}

TEST(TupleCost, TheFamilyWiseGateIsBonferronisLevel) {
  // 1 - (1 - p)/(S(S - 1)/2): 10 pairs for 5 sensors, 3 for 3, none looser for 2.
  EXPECT_NEAR(family_wise_gate_probability(0.99, 5), 0.999, 1e-15);
  EXPECT_NEAR(family_wise_gate_probability(0.99, 3), 1.0 - 0.01 / 3.0, 1e-15);
  EXPECT_EQ(family_wise_gate_probability(0.99, 2), 0.99);
  EXPECT_NEAR(family_wise_gate_probability(0.95, 16), 1.0 - 0.05 / 120.0, 1e-15);
}

}  // namespace
}  // namespace trackassoc
