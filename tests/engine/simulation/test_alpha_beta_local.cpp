// The alpha-beta local filter bank (make_local_filter_bank "ab", engine/simulation/simulation_tracker.cpp):
// two steps and a coast against a hand computation (state and Joseph-form covariance), the steady
// covariance against Kalata's closed form, and the simulator's ab tracks (consistent NEES, accuracy
// beside the CV Kalman filter, 1 vs 2 threads identical).
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_tracker.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// One 2-D track fed by hand: R = 100·I (σ_v = 10 m), σ_w = 1 m/s², T = 1 s.
struct OneTrack {
  std::unique_ptr<LocalFilterBank> bank;
  std::vector<double> z[3], R[6];
  std::vector<uint8_t> detected{0};
  PositionScan scan;
  OneTrack() {
    LocalTrackerSpec spec;
    spec.filter = "ab";
    spec.process_noise = 1.0;
    bank = make_local_filter_bank(spec, 2, 1);
    for (auto& c : z) c.assign(1, 0.0);
    for (auto& c : R) c.assign(1, 0.0);
    R[0][0] = R[2][0] = 100.0;
    for (int a = 0; a < 3; ++a) scan.z[a] = z[a];
    for (int k = 0; k < 6; ++k) scan.R[k] = R[k];
    scan.detected = detected;
    Eigen::Vector2d z1(0.0, 0.0), z2(10.0, 5.0);
    const Eigen::Matrix2d R0 = 100.0 * Eigen::Matrix2d::Identity();
    bank->initialise(0, z1, R0, z2, R0, 1.0);  // plots at t = 0 and t = 1
  }
  void step(double x, double y, bool hit) {
    z[0][0] = x, z[1][0] = y, detected[0] = hit;
    bank->step(1.0, scan);
  }
  void get(Eigen::VectorXd& x, Eigen::MatrixXd& P) const { bank->position_velocity(0, x, P); }
};

// Per axis (pp, pv, vv), axes x, y in the layout (x, y, vx, vy).
void expect_axis_cov(const Eigen::MatrixXd& P, double pp, double pv, double vv, double tol) {
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(P(a, a), pp, tol) << "axis " << a;
    EXPECT_NEAR(P(a, 2 + a), pv, tol) << "axis " << a;
    EXPECT_NEAR(P(2 + a, a), pv, tol) << "axis " << a;
    EXPECT_NEAR(P(2 + a, 2 + a), vv, tol) << "axis " << a;
  }
  // The axes stay uncorrelated with an isotropic R.
  EXPECT_NEAR(P(0, 1), 0.0, tol);
  EXPECT_NEAR(P(0, 3), 0.0, tol);
  EXPECT_NEAR(P(2, 3), 0.0, tol);
}

TEST(AlphaBetaLocal, TwoStepsAndACoastByHand) {
  // Kalata: λ = σ_w T²/σ_v = 0.1, √(λ² + 8λ) = 0.9, α = 0.36, β = 0.08. The expanding-memory gains
  // are larger for n = 2 (g = 5/6, h = 1/2) and n = 3 (g = 7/10, h = 3/10), so those are applied.
  OneTrack t;
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  t.get(x, P);
  // Two-point start: p = z2, v = z2 − z1; P = [[R, R/T], [R/T, 2R/T²]].
  EXPECT_DOUBLE_EQ(x(0), 10.0);
  EXPECT_DOUBLE_EQ(x(3), 5.0);
  expect_axis_cov(P, 100.0, 100.0, 200.0, 1e-12);

  t.step(22.0, 9.0, true);  // t = 2
  t.get(x, P);
  // x: predicted 20, r = 2 → p = 20 + (5/6)·2, v = 10 + (1/2)·2. y: predicted 10, r = −1.
  EXPECT_NEAR(x(0), 20.0 + 5.0 / 3.0, 1e-12);
  EXPECT_NEAR(x(2), 11.0, 1e-12);
  EXPECT_NEAR(x(1), 10.0 - 5.0 / 6.0, 1e-12);
  EXPECT_NEAR(x(3), 4.5, 1e-12);
  // Predicted per axis: pp = 100 + 2·100 + 200 + 1/4 = 500.25, pv = 300.5, vv = 201. Joseph form
  // with K = (5/6, 1/2), R = 100: pp = (1/6)²·500.25 + (5/6)²·100 = 12001/144,
  // pv = (1/6)(−½·500.25 + 300.5) + (5/6)(½)·100 = 801/16, vv = ¼·500.25 − 300.5 + 201 + ¼·100 = 809/16.
  expect_axis_cov(P, 12001.0 / 144.0, 801.0 / 16.0, 809.0 / 16.0, 1e-10);

  t.step(31.0, 14.0, true);  // t = 3
  t.get(x, P);
  // x: predicted 98/3, r = −5/3 → p = 98/3 − 0.7·5/3 = 31.5, v = 11 − 0.3·5/3 = 10.5.
  // y: predicted 55/6 + 4.5 = 41/3, r = 1/3 → p = 41/3 + 0.7/3 = 13.9, v = 4.5 + 0.1 = 4.6.
  EXPECT_NEAR(x(0), 31.5, 1e-12);
  EXPECT_NEAR(x(2), 10.5, 1e-12);
  EXPECT_NEAR(x(1), 13.9, 1e-12);
  EXPECT_NEAR(x(3), 4.6, 1e-12);
  // The same two formulas with K = (0.7, 0.3): 14017/200, 12101/400, 8389/400 (near the
  // least-squares line's 70, 30, 20 for four plots, plus the process noise).
  expect_axis_cov(P, 14017.0 / 200.0, 12101.0 / 400.0, 8389.0 / 400.0, 1e-10);

  t.step(1e9, -1e9, false);  // t = 4, missed: coast, the plot is ignored
  t.get(x, P);
  EXPECT_NEAR(x(0), 42.0, 1e-12);
  EXPECT_NEAR(x(1), 18.5, 1e-12);
  EXPECT_NEAR(x(2), 10.5, 1e-12);
  // F P Fᵀ + Q: pp = 14017/200 + 2·12101/400 + 8389/400 + 1/4 = 2429/16, pv = 2069/40, vv = 8789/400.
  expect_axis_cov(P, 2429.0 / 16.0, 2069.0 / 40.0, 8789.0 / 400.0, 1e-10);
}

TEST(AlphaBetaLocal, SteadyCovarianceIsTheKalataRelation) {
  // After the expanding-memory start the gains settle to α = 0.36, β = 0.08 and the covariance to
  // Kalata's P_pp = ασ_v² = 36, P_pv = βσ_v²/T = 8, P_vv = β(α − β/2)/(1 − α)·σ_v²/T² = 4.
  OneTrack t;
  for (int k = 2; k < 300; ++k) t.step(10.0 * k, 5.0 * k, true);
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  t.get(x, P);
  expect_axis_cov(P, 36.0, 8.0, 4.0, 1e-9);
  // The gains are the steady ones: a residual of 10 moves p by α·10 and v by β·10.
  const double p_pred = x(0) + x(2);
  const double v_before = x(2);
  t.step(p_pred + 10.0, 5.0 * 300, true);
  t.get(x, P);
  EXPECT_NEAR(x(0), p_pred + 3.6, 1e-9);
  EXPECT_NEAR(x(2), v_before + 0.8, 1e-9);
}

TEST(AlphaBetaLocal, ZeroProcessNoiseIsRejected) {
  LocalTrackerSpec spec;
  spec.filter = "ab";
  spec.process_noise = 0.0;
  try {
    make_local_filter_bank(spec, 2, 3);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tracker.process_noise"), std::string::npos) << e.what();
  }
}

// The simulator with tracker.filter = "ab": one radar far away (nearly linear conversion), 200
// white-noise-acceleration targets with the tracker's σ. The propagated covariance is the error
// covariance of the α-β estimate, so the mean NEES is near D = 4; the α-β filter cannot beat the
// Kalman filter of the same model (same σ, exact R) and should not be far behind it.
struct SimStats {
  double nees = 0.0, position_rmse = 0.0;
};
SimStats simulate_stats(const std::string& filter, int threads, TrackTable* out = nullptr) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Scenario sc;
  sc.duration = 60.0;
  sc.random_targets.count = 200;
  sc.random_targets.area_max = {50e3, 50e3, 0};
  sc.random_targets.speed_min = 100;
  sc.random_targets.speed_max = 300;
  sc.random_targets.process_noise = 1.0;
  Sensor radar;
  radar.id = 0;
  radar.position = {-60e3, 0, 0};
  radar.sigma_range = 100.0;
  radar.sigma_bearing = 0.2 * std::numbers::pi / 180;
  radar.period = 1.0;
  radar.p_detect = 0.9;
  sc.sensors = {radar};
  sc.tracker.filter = filter;
  sc.tracker.process_noise = 1.0;
  const SimulationResult r = simulate(sc, 5, 0);
  if (out) *out = r.tracks;
  const auto trajectories = simulate_trajectories(sc, 5, 0);
  std::map<int, const TargetTrajectory*> by_id;
  for (auto& t : trajectories) by_id[t.id] = &t;
  SimStats s;
  int count = 0;
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    if (r.tracks.t[i] < 10.0) continue;  // past the expanding-memory start
    const Kinematics k = by_id.at(r.tracks.truth[i])->at(r.tracks.t[i]);
    Eigen::VectorXd e = r.tracks.state_at(i);
    for (int a = 0; a < 2; ++a) e[a] -= k.p[a], e[2 + a] -= k.v[a];
    s.nees += e.dot(r.tracks.cov_at(i).ldlt().solve(e));
    s.position_rmse += e.head(2).squaredNorm();
    ++count;
  }
  EXPECT_GT(count, 5000);
  s.nees /= count;
  s.position_rmse = std::sqrt(s.position_rmse / count);
  return s;
}

TEST(AlphaBetaLocal, SimulatorTracksAreConsistentAndNearTheKalmanFilter) {
  TrackTable one, two;
  const SimStats ab = simulate_stats("ab", 1, &one);
  simulate_stats("ab", 2, &two);
  EXPECT_EQ(one.state, two.state);
  EXPECT_EQ(one.cov, two.cov);
  const SimStats cv = simulate_stats("cv", 2);
  EXPECT_GT(ab.nees, 0.75 * 4) << "ab NEES";
  EXPECT_LT(ab.nees, 1.4 * 4) << "ab NEES";
  EXPECT_GT(ab.position_rmse, 0.98 * cv.position_rmse);
  EXPECT_LT(ab.position_rmse, 1.5 * cv.position_rmse);
  RecordProperty("ab_nees", std::to_string(ab.nees));
  RecordProperty("ab_rmse_over_cv", std::to_string(ab.position_rmse / cv.position_rmse));
}

}  // namespace
}  // namespace trackassoc
