// The leave-one-out histogram density (kernels/statistics/histogram_density.hpp), by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/statistics/histogram_density.hpp"

namespace trackassoc {
namespace {

TEST(LeaveOneOutHistogram, EachSampleIsScoredAgainstTheOthersOnly) {
  // G = 4, B = ⌈√4⌉ = 2 bins of width 5 over [0, 10]: counts 3 and 1, plus one each (4 and 2).
  // The others of x = 0 hold 2 samples in its bin: (2 + 1) / ((3 + 2) · 5) = 3/25; the lone x = 10
  // leaves its bin with the Laplace count alone: 1/25.
  const std::vector<double> x{0.0, 1.0, 2.0, 10.0};
  const std::vector<double> l = leave_one_out_log_density(x);
  ASSERT_EQ(l.size(), 4u);
  EXPECT_NEAR(l[0], std::log(3.0 / 25.0), 1e-12);
  EXPECT_NEAR(l[1], std::log(3.0 / 25.0), 1e-12);
  EXPECT_NEAR(l[2], std::log(3.0 / 25.0), 1e-12);
  EXPECT_NEAR(l[3], std::log(1.0 / 25.0), 1e-12);
  // Counting x = 10 in its own bin would give 2/(6 · 5) = 1/15, e^0.51 times more.
}

TEST(LeaveOneOutHistogram, ASingleSampleOrEqualSamplesGetTheUnitWidth) {
  // One sample: B = 1 bin of width max(0, 1) = 1 holding only the Laplace count: 1 / ((0 + 1) · 1).
  EXPECT_NEAR(leave_one_out_log_density(std::vector<double>{7.0})[0], 0.0, 1e-12);
  // Nine equal samples: B = 3 bins of width 1/3 over [5, 6]; all in the first: (9 − 1 + 1) / ((8 + 3) / 3).
  const std::vector<double> l = leave_one_out_log_density(std::vector<double>(9, 5.0));
  for (double v : l) EXPECT_NEAR(v, std::log(9.0 * 3.0 / 11.0), 1e-12);
  EXPECT_TRUE(leave_one_out_log_density(std::vector<double>{}).empty());
}

TEST(LeaveOneOutHistogram, EvenlySpreadSamplesByHand) {
  // Samples 0..15: G = 16, B = 4 bins of width 15/4, 4 samples each. The others of any sample hold
  // 3 in its bin, plus the Laplace count: 4 / ((15 + 4) · 15/4). (The others' histogram integrates
  // to 1: its B bins hold G − 1 samples and B Laplace counts, (G − 1 + B) · (w/B) / ((G − 1 + B) w/B).)
  std::vector<double> x;
  for (int i = 0; i < 16; ++i) x.push_back(i);
  for (double v : leave_one_out_log_density(x)) EXPECT_NEAR(v, std::log(4.0 / (19.0 * 15.0 / 4.0)), 1e-12);
}

}  // namespace
}  // namespace trackassoc
