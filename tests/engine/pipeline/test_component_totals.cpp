// The component solves' results summed once (ComponentTotals, engine/pipeline/partition.hpp), the
// rule of both sparse paths, against sums worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/pipeline/partition.hpp"

namespace trackassoc {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ComponentTotals, SumsObjectivesBoundsAndGapsByHand) {
  ComponentTotals t;
  t.add(-10.0, -10.0, "optimal");        // gap 0
  t.add(-20.0, -20.5, "gap_tolerance");  // gap 0.5 / 20 = 2.5 %
  t.add(-4.0, -4.02, "gap_tolerance");   // gap 0.02 / 4 = 0.5 %
  EXPECT_EQ(t.solved, 3);
  EXPECT_DOUBLE_EQ(t.objective, -34.0);
  EXPECT_DOUBLE_EQ(t.lower_bound, -34.52);
  EXPECT_NEAR(t.largest_gap, 0.025, 1e-12);
  EXPECT_EQ(t.above_1pct_gap, 1);
  EXPECT_EQ(t.termination(), "gap_tolerance:2,optimal:1");  // names in order, with their counts
  AssociationRecord rec;
  t.write_to(rec);
  EXPECT_DOUBLE_EQ(rec.objective, -34.0);
  EXPECT_DOUBLE_EQ(rec.lower_bound, -34.52);
  EXPECT_NEAR(rec.gap, 0.52 / 34.0, 1e-12);  // the gap of the sums, not the largest
  EXPECT_EQ(rec.termination, "gap_tolerance:2,optimal:1");
}

TEST(ComponentTotals, OneTerminationIsNamedAloneAndABoundlessComponentLeavesNoBound) {
  ComponentTotals t;
  t.add(-3.0, -3.0, "optimal");
  t.add(-5.0, -5.0, "optimal");
  EXPECT_EQ(t.termination(), "optimal");
  t.add(-7.0, kNaN, "heuristic");  // the merging fallback: no bound
  EXPECT_FALSE(t.bound_known);
  AssociationRecord rec;
  t.write_to(rec);
  EXPECT_DOUBLE_EQ(rec.objective, -15.0);
  EXPECT_TRUE(std::isnan(rec.lower_bound));
  EXPECT_TRUE(std::isnan(rec.gap));
  EXPECT_EQ(rec.termination, "heuristic:1,optimal:2");
  EXPECT_DOUBLE_EQ(t.largest_gap, 0.0);  // over the components with a bound

  ComponentTotals none;  // nothing solved (every component a single track): no bound, no name
  AssociationRecord empty;
  none.write_to(empty);
  EXPECT_DOUBLE_EQ(empty.objective, 0.0);
  EXPECT_TRUE(std::isnan(empty.lower_bound));
  EXPECT_EQ(empty.termination, "");
}

}  // namespace
}  // namespace trackassoc
