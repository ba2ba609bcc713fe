// Fused tracks of an association (engine/fusion/track_fuser.hpp): the time grid of asynchronous
// members worked out by hand, -1 members, segments, tuples without overlap, the rule invariants,
// and, on simulated independent-noise sensors, a fused position RMSE below every sensor's.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <map>
#include <random>

#include "engine/fusion/fused_accuracy.hpp"
#include "engine/fusion/track_fuser.hpp"
#include "engine/simulation/simulation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

std::vector<Sensor> sensors(int n) {
  std::vector<Sensor> s(n);
  for (int i = 0; i < n; ++i) s[i].id = i;
  return s;
}

// A straight track x = x0 + 10 t (vx = 10), y = y0, reported at `times` with covariance P.
void add_track(TrackTable& t, int32_t sensor, int32_t track, const std::vector<double>& times, double x0,
               double y0, const MatrixXd& P, int32_t truth = 0) {
  for (double time : times) {
    VectorXd x(4);
    x << x0 + 10 * time, y0, 10, 0;
    t.push_back(sensor, track, time, x, P, truth);
  }
}

std::vector<double> range(double first, double last, double step) {
  std::vector<double> v;
  for (double t = first; t <= last + 1e-9; t += step) v.push_back(t);
  return v;
}

AssociationRecord association(int32_t S, std::vector<int32_t> tuples) {
  AssociationRecord a;
  a.name = "test";
  a.num_sensors = S;
  a.tuples = std::move(tuples);
  a.cost.assign(a.tuples.size() / S, 0.0);
  return a;
}

TEST(TrackFuser, AsynchronousPairFusesOnTheReportTimesOfTheCommonSpan) {
  // Sensor 0 reports at 0, 2, ..., 8 with P = diag(4, 4, 1, 1); sensor 1 at 3, 5, ..., 11 with
  // P = I. Spans [0, 8] and [3, 11]: the fused times are the reports in [3, 8]: 3, 4, 5, 6, 7, 8.
  TrackTable t;
  const MatrixXd P0 = VectorXd((VectorXd(4) << 4, 4, 1, 1).finished()).asDiagonal();
  add_track(t, 0, 0, range(0, 8, 2), 0, 0, P0);
  add_track(t, 1, 3, range(3, 11, 2), 1, 1, MatrixXd::Identity(4, 4));
  TrackFuserOptions o;
  o.process_noise = 0.0;  // moving a report is then x + Δ·v, F P Fᵀ
  TrackFuserSummary s;
  const FusedTrackRecord r = fuse_association(t, sensors(2), association(2, {0, 3}), o, "f", &s);
  ASSERT_EQ(r.t, (std::vector<double>{3, 4, 5, 6, 7, 8}));
  for (int32_t n : r.sources) EXPECT_EQ(n, 2);
  for (int32_t k : r.tuple) EXPECT_EQ(k, 0);
  EXPECT_EQ(s.fused_tuples, 1);
  EXPECT_EQ(s.rows, 6);
  // At t = 4: sensor 0's own report (40, 0, 10, 0), P0; sensor 1's nearest reports are at 3 and 5
  // (a tie: the earlier one), moved by Δ = 1: (41, 1, 10, 0), per axis [[2, 1], [1, 1]].
  // Per axis, information Y0 = diag(1/4, 1), Y1 = [[1, −1], [−1, 2]], sum [[1.25, −1], [−1, 3]]
  // (det 2.75), P = [[3, 1], [1, 1.25]] / 2.75; x-axis y = Y0 (40, 10) + Y1 (41, 10) = (41, −11),
  // x = (3·41 − 11, 41 − 1.25·11) / 2.75 = (112, 27.25) / 2.75; y-axis y = Y1 (1, 0) = (1, −1),
  // y = (3 − 1, 1 − 1.25) / 2.75.
  const std::size_t i = 1;
  EXPECT_NEAR(r.state[0][i], 112 / 2.75, 1e-9);
  EXPECT_NEAR(r.state[2][i], 27.25 / 2.75, 1e-9);
  EXPECT_NEAR(r.state[1][i], 2 / 2.75, 1e-9);
  EXPECT_NEAR(r.state[3][i], -0.25 / 2.75, 1e-9);
  EXPECT_NEAR(r.cov[packed_index(4, 0, 0)][i], 3 / 2.75, 1e-12);
  EXPECT_NEAR(r.cov[packed_index(4, 0, 2)][i], 1 / 2.75, 1e-12);
  EXPECT_NEAR(r.cov[packed_index(4, 2, 2)][i], 1.25 / 2.75, 1e-12);
  EXPECT_NEAR(r.cov[packed_index(4, 0, 1)][i], 0.0, 1e-12);
}

TEST(TrackFuser, ThreeMembersWithMissingSensorsAndPartialOverlaps) {
  // Spans [0, 10], [5, 20], [15, 30] (reports every second): covered by two where t ∈ [5, 10] ∪
  // [15, 20]; tuple 1 has a −1 column; tuple 2 has one member.
  TrackTable t;
  const MatrixXd I = MatrixXd::Identity(4, 4);
  add_track(t, 0, 0, range(0, 10, 1), 0, 0, I);
  add_track(t, 1, 0, range(5, 20, 1), 0, 0, I);
  add_track(t, 2, 0, range(15, 30, 1), 0, 0, I);
  add_track(t, 0, 1, range(0, 10, 1), 500, 0, I, 1);
  add_track(t, 2, 1, range(0, 10, 1), 500, 0, I, 1);
  add_track(t, 1, 2, range(0, 10, 1), 900, 0, I, 2);
  TrackFuserSummary s;
  const FusedTrackRecord r =
      fuse_association(t, sensors(3), association(3, {0, 0, 0, 1, -1, 1, -1, 2, -1}), {}, "f", &s);
  std::vector<double> expected = range(5, 10, 1);
  for (double x : range(15, 20, 1)) expected.push_back(x);
  std::vector<double> got0, got1;
  for (std::size_t i = 0; i < r.size(); ++i) {
    (r.tuple[i] == 0 ? got0 : got1).push_back(r.t[i]);
    EXPECT_EQ(r.sources[i], 2);
    EXPECT_EQ(r.truth[i], r.tuple[i]);
    if (i > 0) {
      EXPECT_GE(r.tuple[i], r.tuple[i - 1]);
    }
  }
  EXPECT_EQ(got0, expected);
  EXPECT_EQ(got1, range(0, 10, 1));
  EXPECT_EQ(s.tuples, 3);
  EXPECT_EQ(s.fused_tuples, 2);
  EXPECT_EQ(s.single_member, 1);
  // Equal covariances and equal states: the naive fusion is the common state with P/2.
  for (std::size_t i = 0; i < r.size(); ++i) EXPECT_NEAR(r.cov[0][i], 0.5, 1e-12);
}

TEST(TrackFuser, SegmentsOfOnePartnerAreFusedOnTheirOwnTimes) {
  // Sensor 0 track 5 covers 0–100 s; sensor 1 breaks it into track 1 (0–50 s) and track 7
  // (60–100 s), so track 5 is in two tuples. A fourth pair never coexists.
  TrackTable t;
  const MatrixXd I = MatrixXd::Identity(4, 4);
  add_track(t, 0, 5, range(0, 100, 2), 0, 0, I);
  add_track(t, 1, 1, range(0, 50, 5), 0, 0, I);
  add_track(t, 1, 7, range(60, 100, 5), 0, 0, I);
  add_track(t, 0, 6, range(200, 220, 2), 0, 0, I, 1);
  add_track(t, 1, 8, range(230, 240, 5), 0, 0, I, 1);
  TrackFuserSummary s;
  const FusedTrackRecord r = fuse_association(t, sensors(2), association(2, {5, 1, 5, 7, 6, 8}), {}, "f", &s);
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (r.tuple[i] == 0) {
      EXPECT_TRUE(r.t[i] >= 0 && r.t[i] <= 50) << r.t[i];
    }
    if (r.tuple[i] == 1) {
      EXPECT_TRUE(r.t[i] >= 60 && r.t[i] <= 100) << r.t[i];
    }
    EXPECT_NE(r.tuple[i], 2);
  }
  EXPECT_EQ(s.fused_tuples, 2);
  EXPECT_EQ(s.no_overlap, 1);
  // The union of the report times in each common span: in [0, 50] 26 of sensor 0 (every 2 s) and
  // 11 of sensor 1 (every 5 s), 6 of them shared (0, 10, ..., 50): 31; in [60, 100] 21 + 9 − 5 = 25.
  int64_t first = 0, second = 0;
  for (int32_t k : r.tuple) first += k == 0, second += k == 1;
  EXPECT_EQ(first, 31);
  EXPECT_EQ(second, 25);
}

TEST(TrackFuser, DuplicateTracksOfATargetHandOverTheirSlot) {
  // Sensor 1 holds track 1 (0–100 s, every 5 s) and, from 40 to 70 s, its duplicate 7 of the same
  // target; the segment pass writes tuples {5, 1} and {5, 7} of target 0 (slices: 1, then 7 while
  // it reports, then 1 again). Track 1 hands its slot over during [40, 70], so each of track 5's
  // reports is fused once. Hand counts (union of the report times where both members are active):
  // tuple 1 over [40, 70]: 16 (sensor 0, every 2 s) + 7 (track 7) − 4 shared = 19; tuple 0 over
  // [0, 40): 20 + 8 − 4 = 24 and over (70, 100]: 15 + 6 − 3 = 18, 42 in all.
  TrackTable t;
  const MatrixXd I = MatrixXd::Identity(4, 4);
  add_track(t, 0, 5, range(0, 100, 2), 0, 0, I);
  add_track(t, 1, 1, range(0, 100, 5), 0, 0, I);
  add_track(t, 1, 7, range(40, 70, 5), 0, 2, I);
  AssociationRecord a = association(2, {5, 1, 5, 7});
  a.target = {0, 0};
  const FusedTrackRecord r = fuse_association(t, sensors(2), a, {}, "f");
  int64_t rows0 = 0, rows1 = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (r.tuple[i] == 0) {
      ++rows0;
      EXPECT_TRUE(r.t[i] < 40 || r.t[i] > 70) << r.t[i];
    } else {
      ++rows1;
      EXPECT_TRUE(r.t[i] >= 40 && r.t[i] <= 70) << r.t[i];
    }
  }
  EXPECT_EQ(rows0, 42);
  EXPECT_EQ(rows1, 19);
  // Without target numbers the two tuples are unrelated: tuple 0 over all of [0, 100], 51 + 21 − 11.
  a.target.clear();
  const FusedTrackRecord plain = fuse_association(t, sensors(2), a, {}, "f");
  EXPECT_EQ(std::count(plain.tuple.begin(), plain.tuple.end(), 0), 61);
}

TEST(TrackFuser, RuleInvariantsOnEveryRow) {
  // Two noisy tracks of one target: BSC with rho = 0 is the naive rule; CI's covariance is never
  // below the naive one nor below BSC's with the same (rho) cross-covariance, in the trace sense.
  TrackTable t;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n;
  for (int s = 0; s < 2; ++s)
    for (double time : range(s * 0.7, 60, 1.0 + s)) {
      VectorXd x(4);
      x << 10 * time + 30 * n(rng), 20 * n(rng), 10 + n(rng), n(rng);
      MatrixXd P = MatrixXd::Identity(4, 4) * (s ? 400.0 : 900.0);
      P(0, 2) = P(2, 0) = P(1, 3) = P(3, 1) = 20.0 + 10 * s;
      P(2, 2) = P(3, 3) = 4.0;
      t.push_back(s, 0, time, x, P, 0);
    }
  const AssociationRecord a = association(2, {0, 0});
  auto fuse = [&](FusionRule rule, double rho) {
    TrackFuserOptions o;
    o.rule = rule;
    o.correlation = rho;
    return fuse_association(t, sensors(2), a, o, "f");
  };
  const FusedTrackRecord naive = fuse(FusionRule::kNaive, -1), bsc0 = fuse(FusionRule::kBarShalomCampo, 0.0),
                         bsc = fuse(FusionRule::kBarShalomCampo, 0.4),
                         ci = fuse(FusionRule::kCovarianceIntersection, -1);
  ASSERT_GT(naive.size(), 50u);
  ASSERT_EQ(ci.size(), naive.size());
  ASSERT_EQ(ci.omega.size(), 2 * ci.size());
  auto trace = [](const FusedTrackRecord& r, std::size_t i) {
    double tr = 0;
    for (int c = 0; c < 4; ++c) tr += r.cov[packed_index(4, c, c)][i];
    return tr;
  };
  for (std::size_t i = 0; i < naive.size(); ++i) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(bsc0.state[c][i], naive.state[c][i], 1e-9);
    EXPECT_NEAR(trace(bsc0, i), trace(naive, i), 1e-9);
    EXPECT_GE(trace(ci, i), trace(naive, i) - 1e-9);
    EXPECT_GE(trace(ci, i), trace(bsc, i) - 1e-9);
    EXPECT_GT(trace(bsc, i), trace(naive, i));  // positive correlation: less information
    EXPECT_NEAR(ci.omega[2 * i] + ci.omega[2 * i + 1], 1.0, 1e-12);
  }
}

TEST(TrackFuser, OptionsNeedOneCrossCovarianceForBscOnly) {
  TrackFuserOptions o;
  o.rule = FusionRule::kBarShalomCampo;
  EXPECT_THROW(o.validate(), InputError);  // neither
  o.common_process_noise = 1.0;
  o.correlation = 0.2;
  EXPECT_THROW(o.validate(), InputError);  // both
  o.correlation = -1.0;
  EXPECT_NO_THROW(o.validate());
  o.rule = FusionRule::kNaive;
  EXPECT_THROW(o.validate(), InputError);  // sigma without bsc
}

TEST(TrackFuser, FileWithoutScenarioRefusesBscWithoutACrossCovariance) {
  TrackFile f;
  f.sensors = sensors(2);
  add_track(f.tracks, 0, 0, range(0, 10, 1), 0, 0, MatrixXd::Identity(4, 4));
  add_track(f.tracks, 1, 0, range(0, 10, 1), 0, 0, MatrixXd::Identity(4, 4));
  f.associations.push_back(association(2, {0, 0}));
  TrackFuserOptions o;
  o.rule = FusionRule::kBarShalomCampo;
  try {
    fuse_track_file(f, "", "", o);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--common-process-noise"), std::string::npos) << e.what();
  }
  EXPECT_THROW(fuse_track_file(f, "other", "", {}), InputError);
  const TrackFuserSummary s = fuse_track_file(f, "", "", {});
  ASSERT_EQ(f.fused.size(), 1u);
  EXPECT_EQ(f.fused[0].name, "test");
  EXPECT_EQ(s.rows, 11);
  fuse_track_file(f, "test", "", {});  // the same name again: replaced, not duplicated
  EXPECT_EQ(f.fused.size(), 1u);
}

// Two radars with independent measurement noise, asynchronous (2 s and 3 s), targets with little
// process noise; the association is the true one. Fusion must beat each radar's own tracks.
TEST(TrackFuser, FusedRmseBelowEachSensorsOnIndependentNoise) {
  Scenario sc;
  sc.duration = 120;
  sc.random_targets.count = 10;
  sc.random_targets.area_min = {-20e3, -20e3, 0};
  sc.random_targets.area_max = {20e3, 20e3, 0};
  sc.random_targets.speed_min = 100, sc.random_targets.speed_max = 250;
  sc.random_targets.process_noise = 0.5;
  sc.tracker.process_noise = 1.0;
  for (int s = 0; s < 2; ++s) {
    Sensor x;
    x.id = s;
    x.position = {-50e3 + 100e3 * s, 10e3 * s, 0};
    x.sigma_range = 50.0 + 30 * s;
    x.sigma_bearing = (0.2 + 0.1 * s) * 0.017453292519943295;
    x.period = 2.0 + s;
    x.offset = 0.5 * s;
    sc.sensors.push_back(x);
  }
  const SimulationResult sim = simulate(sc, 7, 0);
  // The true association: per target, its track on each sensor.
  std::map<int32_t, std::array<int32_t, 2>> by_target;
  for (std::size_t r = 0; r < sim.tracks.size(); ++r) {
    auto [it, fresh] = by_target.try_emplace(sim.tracks.truth[r], std::array<int32_t, 2>{-1, -1});
    it->second[sim.tracks.sensor[r]] = sim.tracks.track[r];
  }
  std::vector<int32_t> tuples;
  for (const auto& [target, pair] : by_target) tuples.insert(tuples.end(), pair.begin(), pair.end());
  const AssociationRecord a = association(2, tuples);
  for (FusionRule rule :
       {FusionRule::kNaive, FusionRule::kBarShalomCampo, FusionRule::kCovarianceIntersection}) {
    TrackFuserOptions o;
    o.rule = rule;
    if (rule == FusionRule::kBarShalomCampo) o.common_process_noise = sc.tracker.process_noise;
    const FusedTrackRecord r = fuse_association(sim.tracks, sc.sensors, a, o, "f");
    const FusedAccuracy acc = evaluate_fused(sim.tracks, sc.sensors, sim.truth, r);
    ASSERT_GT(acc.fused_rows, 500) << enum_name(rule);
    ASSERT_GT(acc.sensor_rows[0], 300);
    ASSERT_GT(acc.sensor_rows[1], 200);
    EXPECT_EQ(acc.rows_without_truth, 0);
    const double best = std::min(acc.sensor_rmse[0], acc.sensor_rmse[1]);
    if (rule == FusionRule::kCovarianceIntersection)
      EXPECT_LT(acc.fused_rmse, std::max(acc.sensor_rmse[0], acc.sensor_rmse[1])) << enum_name(rule);
    else
      EXPECT_LT(acc.fused_rmse, best) << enum_name(rule) << ": fused " << acc.fused_rmse << " m, sensors "
                                      << acc.sensor_rmse[0] << ", " << acc.sensor_rmse[1] << " m";
    std::cout << enum_name(rule) << ": fused " << acc.fused_rmse << " m (" << acc.fused_rows
              << " rows), sensor 0 " << acc.sensor_rmse[0] << " m, sensor 1 " << acc.sensor_rmse[1] << " m\n";
  }
}

TEST(FusedAccuracy, TruthInterpolationIsExactForConstantAcceleration) {
  // x(t) = 3 + 2t + 0.5·1.5 t², sampled every 2 s with its velocity: Hermite gives it exactly.
  TruthTable truth;
  for (double time : range(0, 10, 2)) {
    truth.target.push_back(4);
    truth.t.push_back(time);
    truth.state[0].push_back(3 + 2 * time + 0.75 * time * time);
    truth.state[1].push_back(-1.0);
    truth.state[2].push_back(2 + 1.5 * time);
    truth.state[3].push_back(0.0);
  }
  const TruthInterpolator interp(truth);
  for (double time : {0.0, 0.3, 3.7, 9.99, 10.0}) {
    const auto p = interp.position(4, time);
    ASSERT_TRUE(p.has_value());
    EXPECT_NEAR((*p)[0], 3 + 2 * time + 0.75 * time * time, 1e-9) << time;
    EXPECT_NEAR((*p)[1], -1.0, 1e-12);
  }
  EXPECT_FALSE(interp.position(4, 10.5).has_value());
  EXPECT_FALSE(interp.position(5, 1.0).has_value());
}

}  // namespace
}  // namespace trackassoc
