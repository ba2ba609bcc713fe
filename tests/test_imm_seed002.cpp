// The seed 002 study at a small scale: deterministic for 1 and 2 threads, finite curves, and the
// qualitative claims the paper makes that hold by construction of the IMM.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>

#include "engine/experiment_seed002.hpp"
#include "kernels/error.hpp"

namespace trackassoc {
namespace {

TEST(Seed002, SmallStudyIsDeterministicAndSane) {
  Seed002Options o;
  o.runs = 16;
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    return run_seed002(o);
  };
  const Seed002Result a = run(1), b = run(2);
  ASSERT_EQ(a.motions.size(), 4u);
  for (std::size_t m = 0; m < 4; ++m) {
    EXPECT_EQ(a.motions[m].rmse_imm, b.motions[m].rmse_imm);
    EXPECT_EQ(a.motions[m].rmse_cs_parallel, b.motions[m].rmse_cs_parallel);
    EXPECT_EQ(a.motions[m].t.size(), 100u);
    for (int q = 0; q < 3; ++q) {
      EXPECT_TRUE(std::isfinite(a.motions[m].ratio[q]));
      EXPECT_GT(a.motions[m].ratio[q], 0.0);
    }
    // Position RMSE stays at the level of the measurement error (30–60 m cross-range, 50 m range).
    for (double e : a.motions[m].rmse_imm[0]) EXPECT_LT(e, 200.0);
  }
  // The IMM's model probabilities are probabilities.
  for (const auto& m : a.motions)
    for (double p : m.imm_prob_cs) {
      EXPECT_GE(p, 0.0);
      EXPECT_LE(p, 1.0);
    }
  // The circle (30 m/s² throughout) is where mixing in the CA model helps most: ratio < 1.
  EXPECT_LT(a.motions[1].ratio[0], 1.0);
}

TEST(Seed002, RejectsBadRuns) {
  Seed002Options o;
  o.runs = 0;
  EXPECT_THROW(run_seed002(o), InputError);
}

}  // namespace
}  // namespace trackassoc
