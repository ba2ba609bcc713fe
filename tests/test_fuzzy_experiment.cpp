// The seed 001 experiment (engine/experiment_seed001.hpp) on a few runs: the scenario matches the
// paper's setting, the figures are bit-identical for 1 and 2 threads, both methods associate the
// two targets, and the proposed method's RMSE is below FTAA's (seed 001 Table 1's ordering).
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "engine/experiment_seed001.hpp"

using namespace trackassoc;

TEST(Seed001Experiment, ScenarioIsThePapers) {
  const Scenario s = seed001_scenario(Seed001Options{});
  ASSERT_EQ(s.sensors.size(), 4u);
  ASSERT_EQ(s.targets.size(), 2u);
  EXPECT_EQ(s.targets[0].initial_state[0], -29500.0);
  EXPECT_EQ(s.targets[0].initial_state[3], 290.0);    // vx
  EXPECT_EQ(s.targets[1].initial_state[1], 32500.0);  // y
  EXPECT_EQ(s.targets[1].initial_state[4], -400.0);   // vy
  EXPECT_EQ(s.sensors[3].sigma_range, 120.0);
  EXPECT_NEAR(s.sensors[0].sigma_bearing, std::numbers::pi / 180.0, 1e-15);
  EXPECT_EQ(s.sensors[3].reliability, 0.6);
  EXPECT_EQ(s.sensors[2].offset, 2.0);
}

TEST(Seed001Experiment, DeterministicAndProposedBelowFtaa) {
  Seed001Options o;
  o.runs = 6;
  auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    return run_seed001(o);
  };
  const Seed001Result a = run(1), b = run(2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(a.fuzzy.mean_rmse[k], b.fuzzy.mean_rmse[k]);
    EXPECT_EQ(a.ftaa.mean_rmse[k], b.ftaa.mean_rmse[k]);
    EXPECT_EQ(a.fuzzy.rmse[k].size(), b.fuzzy.rmse[k].size());
    EXPECT_LT(a.fuzzy.mean_rmse[k], a.ftaa.mean_rmse[k]) << "target " << k;
    EXPECT_GT(a.fuzzy.mean_rmse[k], 0.0);
  }
  EXPECT_NEAR(a.fuzzy.correct_rate, 1.0, 1e-12);
  EXPECT_NEAR(a.ftaa.correct_rate, 1.0, 1e-12);
  EXPECT_EQ(a.example.system_tracks.size(), 2u);
  EXPECT_EQ(a.example.associations.size(), 2u);
}
