// The swap margin of stitching's joins (engine/pipeline/stitch_swap_margin.hpp), by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "engine/pipeline/stitch_swap_margin.hpp"

namespace trackassoc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Groups 0..5. Ends 0 and 1 gate starts 2 and 3 crosswise: c(0,2) = −10, c(1,3) = −10 (joined),
// c(0,3) = −9, c(1,2) = −9.5. End 4 gates start 5 alone (−2). The swap of 0 and 1's successors
// costs −9 − 9.5 against −20: margin 1.5 for both joins, from either side:
//   end 0 takes 3, its predecessor 1 takes 2: −9 + min(0, −9.5) − (−10) = −8.5, minus −10 = 1.5;
//   start 2 is taken by 1, whose successor 3 goes to 0: −9.5 + min(0, −9) − (−10) = −8.5 → 1.5.
// The lone join 4 → 5 has no rival: +inf. Ends 2, 3 and 5 have no join: +inf.
TEST(StitchSwapMargin, ACrossedPairByHand) {
  const std::vector<int32_t> end{0, 0, 1, 1, 4}, start{2, 3, 2, 3, 5};
  const std::vector<double> cost{-10.0, -9.0, -9.5, -10.0, -2.0};
  const std::vector<int32_t> successor{2, 3, -1, -1, 5, -1};
  const std::vector<double> m = stitch_swap_margins(6, {end, start, cost}, successor);
  ASSERT_EQ(m.size(), 6u);
  EXPECT_NEAR(m[0], 1.5, 1e-12);
  EXPECT_NEAR(m[1], 1.5, 1e-12);
  EXPECT_EQ(m[4], kInf);
  EXPECT_EQ(m[2], kInf);
  EXPECT_EQ(m[5], kInf);
}

// A rival start with no predecessor: end 0, joined to 1 (−10), could take 2 instead (−8; 2 has no
// predecessor): −8 − (−10) = 2. The rival end 3 of start 1 would give up its successor 4 (−6),
// which end 0 cannot take ((0, 4) is no candidate: nothing): −7 + 0 − (−6) = −1, minus −10: 9.
// The margin is the smaller: 2.
TEST(StitchSwapMargin, AFreeRivalStartAndAnEndWhoseSuccessorHasNoOtherTaker) {
  const std::vector<int32_t> end{0, 0, 3, 3}, start{1, 2, 1, 4};
  const std::vector<double> cost{-10.0, -8.0, -7.0, -6.0};
  const std::vector<int32_t> successor{1, -1, -1, 4, -1};
  const std::vector<double> m = stitch_swap_margins(5, {end, start, cost}, successor);
  EXPECT_NEAR(m[0], 2.0, 1e-12);
  // End 3's join to 4: its rival start 1 has predecessor 0, which would take 4 (no pair: nothing):
  //   −7 + 0 − (−10) = 3, minus −6: 9.
  EXPECT_NEAR(m[3], 9.0, 1e-12);
}

TEST(StitchSwapMargin, AJoinThatIsNoCandidateIsABug) {
  const std::vector<int32_t> end{0}, start{1};
  const std::vector<double> cost{-1.0};
  const std::vector<int32_t> successor{2, -1, -1};
  EXPECT_THROW(stitch_swap_margins(3, {end, start, cost}, successor), std::invalid_argument);
}

}  // namespace
}  // namespace trackassoc
