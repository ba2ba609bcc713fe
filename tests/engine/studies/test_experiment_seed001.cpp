// The seed 001 experiment (engine/studies/seed001/experiment_seed001.hpp): the scenario matches the paper's
// setting under both readings of σθ₁, the 0.1° erratum makes node 1's plots as accurate as node 3's (so the
// measurement covariances follow the reliabilities), plot packets carry the converted measurement and
// a temporary track's velocity is the two-plot difference (hand arithmetic), the α-β design gives
// Kalata's gains (hand calculation), FTAA runs with the paper's m ≥ 6, D ≥ 6, the figures are
// bit-identical for 1 and 2 threads, both methods associate the two targets, and the proposed
// method's RMSE is below FTAA's (seed 001 Table 1's ordering).
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "engine/simulation/simulation.hpp"
#include "engine/studies/seed001/experiment_seed001.hpp"
#include "kernels/core/error.hpp"
#include "kernels/filters/kalman_converted.hpp"

using namespace trackassoc;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

TEST(Seed001Experiment, ScenarioIsThePapers) {
  const Scenario s = seed001_scenario(Seed001Options{});
  ASSERT_EQ(s.sensors.size(), 4u);
  ASSERT_EQ(s.targets.size(), 2u);
  EXPECT_EQ(s.targets[0].initial_state[0], -29500.0);
  EXPECT_EQ(s.targets[0].initial_state[3], 290.0);    // vx
  EXPECT_EQ(s.targets[1].initial_state[1], 32500.0);  // y
  EXPECT_EQ(s.targets[1].initial_state[4], -400.0);   // vy
  EXPECT_EQ(s.sensors[3].sigma_range, 120.0);
  EXPECT_EQ(s.sensors[3].reliability, 0.6);
  EXPECT_EQ(s.sensors[2].offset, 2.0);
  // Default: the erratum σθ₁ = 0.1°; as printed: 1°. Nodes 2–4 are the same in both.
  EXPECT_NEAR(s.sensors[0].sigma_bearing, 0.1 * kDeg, 1e-15);
  Seed001Options literal;
  literal.bearing_reading = BearingReading::kLiteral;
  const Scenario l = seed001_scenario(literal);
  EXPECT_NEAR(l.sensors[0].sigma_bearing, 1.0 * kDeg, 1e-15);
  for (int k = 1; k < 4; ++k) EXPECT_EQ(l.sensors[k].sigma_bearing, s.sensors[k].sigma_bearing);
  EXPECT_NEAR(s.sensors[1].sigma_bearing, 0.12 * kDeg, 1e-15);
  EXPECT_NEAR(s.sensors[2].sigma_bearing, 0.1 * kDeg, 1e-15);
  EXPECT_EQ(parse_enum<BearingReading>("literal", "reading"), BearingReading::kLiteral);
  EXPECT_THROW(parse_enum<BearingReading>("1deg", "reading"), InputError);
}

TEST(Seed001Experiment, ErratumMakesTheCovariancesFollowTheReliabilities) {
  // At a common range and bearing, node 1 and node 3 (both ω = 1.0, σr = 50 m) have the same
  // converted covariance only under the 0.1° reading. At bearing 0, R = diag(σr², (r σθ)²).
  const Scenario s = seed001_scenario(Seed001Options{});
  Seed001Options lo;
  lo.bearing_reading = BearingReading::kLiteral;
  const Scenario l = seed001_scenario(lo);
  for (double r : {20000.0, 50000.0, 70000.0})
    for (double th : {0.0, 0.7, -2.1}) {
      const auto a = convert_polar(2, s.sensors[0], r, th, 0.0),
                 b = convert_polar(2, s.sensors[2], r, th, 0.0);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.R[k], b.R[k], 1e-9 * (1 + std::abs(b.R[k])));
    }
  const auto e0 = convert_polar(2, s.sensors[0], 50000.0, 0.0, 0.0);
  const auto l0 = convert_polar(2, l.sensors[0], 50000.0, 0.0, 0.0);
  EXPECT_NEAR(e0.R[0], 2500.0, 1e-9);
  EXPECT_NEAR(e0.R[2], std::pow(50000.0 * 0.1 * kDeg, 2), 1e-6);  // (87.27 m)²
  EXPECT_NEAR(l0.R[2], std::pow(50000.0 * 1.0 * kDeg, 2), 1e-6);  // (872.7 m)²: 100 × node 3's
  // The reliabilities 1.0 > 0.8 > 0.6 order the plots' accuracy (trace of R) over the targets'
  // 20–70 km only under the erratum; under the literal reading node 1 is the worst at 50 km.
  auto trace = [](const Sensor& n, double r) {
    const auto m = convert_polar(2, n, r, 0.3, 0.0);
    return m.R[0] + m.R[2];
  };
  for (double r : {20000.0, 50000.0, 70000.0}) {
    EXPECT_LT(trace(s.sensors[0], r), trace(s.sensors[1], r)) << r;
    EXPECT_LT(trace(s.sensors[1], r), trace(s.sensors[3], r)) << r;
  }
  for (int k = 1; k < 4; ++k) EXPECT_GT(trace(l.sensors[0], 50000.0), trace(l.sensors[k], 50000.0));
  // The pooled per-axis plot σ of the smoother design: (1/8) Σ (σr² + (R σθ)²) at R = 50 km,
  // by hand (2500 + 7615.5 + 10000 + 10966.2 + 2500 + 7615.5 + 14400 + 10966.2) / 8 = 8320.4 m².
  EXPECT_NEAR(seed001_plot_sigma(BearingReading::kErratum, 50000.0), std::sqrt(8320.42), 0.01);
  // Literal: node 1's term is 2500 + 761 524.4 instead: 102 561.4 m².
  EXPECT_NEAR(seed001_plot_sigma(BearingReading::kLiteral, 50000.0), std::sqrt(102561.4), 0.01);
}

TEST(Seed001Experiment, SmootherDesignIsKalatas) {
  // Kalata 1984 Eq. 27–28 by hand. λ = 1: √(1 + 8) = 3, α = −(1 + 8 − 5·3)/8 = 0.75,
  // β = (1 + 4 − 3)/4 = 0.5. Set σ_w = σ_v so that λ = σ_w T²/σ_v = 1 at T = 1 s.
  Seed001Options o;
  o.smoother_process_noise = seed001_plot_sigma(o.bearing_reading, o.design_range);
  AlphaBetaOptions ab = seed001_smoother(o);
  EXPECT_EQ(ab.gains, AlphaBetaGainMode::kKalata);
  EXPECT_TRUE(ab.expanding_memory_start);
  AlphaBetaGains g = alpha_beta_gains(ab, 1.0);
  EXPECT_NEAR(g.alpha, 0.75, 1e-12);
  EXPECT_NEAR(g.beta, 0.5, 1e-12);
  // The default design, σ_w = 0.1 m/s², σ_v = 91.216 m: λ = 0.1/91.216 = 1.09630e-3,
  // √(λ² + 8λ) = 0.0936535, α = −(λ² + 8λ − (λ + 4)·0.0936535)/8 = 0.0457447,
  // β = (λ² + 4λ − λ·0.0936535)/4 = 1.07093e-3.
  ab = seed001_smoother(Seed001Options{});
  EXPECT_NEAR(ab.measurement_noise, 91.2163, 1e-3);
  g = alpha_beta_gains(ab, 1.0);
  EXPECT_NEAR(g.alpha, 0.0457447, 1e-6);
  EXPECT_NEAR(g.beta, 1.07093e-3, 1e-8);
  // The study runs with the designed smoother.
  Seed001Options two;
  two.runs = 1;
  EXPECT_EQ(run_seed001(two).smoother.measurement_noise, ab.measurement_noise);
}

TEST(Seed001Experiment, FtaaUsesThePapersThresholds) {
  const Seed001Options o;
  EXPECT_EQ(o.ftaa.association_quality, 6);  // seed 001 §1: m ≥ 6
  EXPECT_EQ(o.ftaa.separation_quality, 6);   // D ≥ 6
  EXPECT_EQ(o.ftaa.gate, 800.0);
  EXPECT_EQ(o.packet_source, PacketSource::kPlot);
  EXPECT_EQ(o.bearing_reading, BearingReading::kErratum);
}

TEST(Seed001Experiment, PlotPacketsAndTwoPlotTemporaryTracks) {
  const Seed001Options o;
  const Scenario sc = seed001_scenario(o);
  const SimulationResult sim = simulate(sc, o.seed, 0);
  const PacketTable p =
      make_packets(sim.tracks, sc.sensors, o.packet_period, PacketSource::kPlot, &sim.measurements);
  ASSERT_GT(p.size(), 100u);
  // Every packet is one plot: sensor position + r (cos θ, sin θ) of the measurement of its sensor,
  // target and time (a hand conversion).
  const Measurements& m = sim.measurements;
  std::size_t checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Sensor& n = sc.sensors[p.sensor[i]];
    for (std::size_t k = 0; k < m.size(); ++k)
      if (m.sensor[k] == n.id && m.target[k] == p.truth[i] && std::abs(m.t[k] - p.t[i]) < 1e-9) {
        EXPECT_NEAR(p.x[i], n.position[0] + m.range[k] * std::cos(m.bearing[k]), 1e-6);
        EXPECT_NEAR(p.y[i], n.position[1] + m.range[k] * std::sin(m.bearing[k]), 1e-6);
        ++checked;
      }
  }
  EXPECT_EQ(checked, p.size());
  // One local track's first two packets, 4 s apart, form the first temporary track: a new system
  // track starts at the second plot with velocity (x2 − x1)/(t2 − t1).
  const std::size_t first = 0;
  std::size_t second = p.size();
  for (std::size_t i = 1; i < p.size() && second == p.size(); ++i)
    if (p.local[i] == p.local[first]) second = i;
  ASSERT_LT(second, p.size());
  EXPECT_NEAR(p.t[second] - p.t[first], o.packet_period, 1e-9);
  FuzzyAssociator fc(o.fuzzy, std::vector<double>{1.0, 0.8, 1.0, 0.6}, p.num_local());
  EXPECT_EQ(fc.process(p.sensor[first], p.local[first], p.t[first], p.x[first], p.y[first]).system_track, -1);
  const auto d = fc.process(p.sensor[second], p.local[second], p.t[second], p.x[second], p.y[second]);
  EXPECT_TRUE(d.new_track);
  EXPECT_DOUBLE_EQ(d.fused.x, p.x[second]);
  EXPECT_NEAR(d.fused.vx, (p.x[second] - p.x[first]) / 4.0, 1e-9);
  EXPECT_NEAR(d.fused.vy, (p.y[second] - p.y[first]) / 4.0, 1e-9);
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

TEST(Seed001Experiment, PlotNoiseModelExplainsTheMeasuredRmse) {
  // Under the erratum every association is right, so the plot-noise model (an independent
  // covariance propagation, no simulation) must predict the Monte Carlo RMSE; it is a little low
  // because it uses the nominal 50 km range for every plot.
  Seed001Options o;
  o.runs = 20;
  const Seed001Result r = run_seed001(o);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(r.fuzzy.mean_rmse[k] / r.model.proposed_rmse, 1.0, 0.15) << "target " << k;
    EXPECT_NEAR(r.ftaa.mean_rmse[k] / r.model.ftaa_rmse, 1.0, 0.15) << "target " << k;
  }
  // A larger σ_w (less smoothing) raises both the model and the measured RMSE of the proposed method.
  Seed001Options loose = o;
  loose.smoother_process_noise = 2.0;
  const Seed001Result q = run_seed001(loose);
  EXPECT_GT(q.model.proposed_rmse, r.model.proposed_rmse * 1.3);
  for (int k = 0; k < 2; ++k) EXPECT_GT(q.fuzzy.mean_rmse[k], r.fuzzy.mean_rmse[k] * 1.3);
}
