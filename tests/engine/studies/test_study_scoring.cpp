// The paper studies score what users get, and seed 000's correlated errors (issue 14):
//  * the Bar-Shalom–Campo cross-covariance from common process noise
//  (kernels/statistics/cross_covariance.hpp)
//    against Kalman filters written out here: the gain read off the reported covariances equals
//    the filter's own I − KH; the recursion equals the Monte Carlo cross-covariance of two filters
//    that track one target; each scan term of the correlated statistic equals dᵀ(P_a + P_b − P_ab −
//    P_ba)⁻¹d computed from the filters' true gains;
//  * every row of `experiment seed000` equals `simulate` + `associate` + `evaluate` on the same seeds,
//    every row of `experiment seed004` equals `associate --sd` + `evaluate` on the same file, and
//    the TTCSN rate of `experiment seed003` equals `associate --solver siamese` + `evaluate` on
//    the scene written as a track file; the correct rates of `experiment seed001` (run 0) equal
//    `associate --solver fuzzy|ftaa` with the options it stored, then `evaluate`, on its own file.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/siamese_track_file.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/seed000/experiment_seed000.hpp"
#include "engine/studies/seed003/experiment_seed003.hpp"
#include "engine/studies/seed004/experiment_seed004.hpp"
#include "io/scenario_json.hpp"
#include "io/siamese_model_file.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cross_covariance.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

constexpr int kD = 4;                      // 2-D CV state (x, y, vx, vy)
constexpr double kT = 2.0, kSigmaA = 3.0;  // scan period [s], white-noise acceleration [m/s²]

// One run of two position-measuring CV Kalman filters (σ_r = 100 m and 250 m) on one target with
// white-noise acceleration σ_a, the filters' own model. Step 0 is the independent start.
struct TwoFilterRun {
  std::vector<Eigen::VectorXd> truth, xa, xb;
  std::vector<Eigen::MatrixXd> Pa, Pb, Aa, Ab;  // Aa[k] = I − K_a(k)H (identity at 0)
};

TwoFilterRun run_two_filters(std::mt19937_64& rng, int steps) {
  std::normal_distribution<double> n01;
  Eigen::MatrixXd F, Q;
  cv_transition(kD, kT, kSigmaA, F, Q);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2, kD);
  H(0, 0) = H(1, 1) = 1.0;
  const double ra = 100.0, rb = 250.0;
  Eigen::MatrixXd P0 = Eigen::MatrixXd::Zero(kD, kD);
  P0.diagonal() << 300.0 * 300.0, 300.0 * 300.0, 50.0 * 50.0, 50.0 * 50.0;
  const Eigen::MatrixXd L0 = P0.llt().matrixL();
  TwoFilterRun r;
  Eigen::VectorXd x(kD);
  x << 1e4, 2e4, 150.0, -80.0;
  auto noise = [&](int n) {
    Eigen::VectorXd z(n);
    for (int i = 0; i < n; ++i) z(i) = n01(rng);
    return z;
  };
  Eigen::VectorXd xa = x + L0 * noise(kD), xb = x + L0 * noise(kD);
  Eigen::MatrixXd Pa = P0, Pb = P0;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(kD, kD);
  r.truth.push_back(x), r.xa.push_back(xa), r.xb.push_back(xb);
  r.Pa.push_back(Pa), r.Pb.push_back(Pb), r.Aa.push_back(I), r.Ab.push_back(I);
  for (int k = 1; k <= steps; ++k) {
    Eigen::VectorXd w(2);
    w << kSigmaA * n01(rng), kSigmaA * n01(rng);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(kD, 2);  // per axis (T²/2, T): Q = σ_a²·G Gᵀ
    G(0, 0) = G(1, 1) = kT * kT / 2.0;
    G(2, 0) = G(3, 1) = kT;
    x = F * x + G * w;
    auto update = [&](Eigen::VectorXd& xh, Eigen::MatrixXd& P, double sr, Eigen::MatrixXd& A) {
      const Eigen::VectorXd z = H * x + sr * noise(2);
      const Eigen::MatrixXd Pp = F * P * F.transpose() + Q;
      const Eigen::MatrixXd S = H * Pp * H.transpose() + sr * sr * Eigen::MatrixXd::Identity(2, 2);
      const Eigen::MatrixXd K = Pp * H.transpose() * S.inverse();
      xh = F * xh + K * (z - H * F * xh);
      A = I - K * H;
      P = A * Pp * A.transpose() + K * (sr * sr) * K.transpose();  // Joseph form
    };
    Eigen::MatrixXd Aa, Ab;
    update(xa, Pa, ra, Aa);
    update(xb, Pb, rb, Ab);
    r.truth.push_back(x), r.xa.push_back(xa), r.xb.push_back(xb);
    r.Pa.push_back(Pa), r.Pb.push_back(Pb), r.Aa.push_back(Aa), r.Ab.push_back(Ab);
  }
  return r;
}

// One sensor's track of run r as AlignedTracks at the scan times.
AlignedTracks aligned(const std::vector<Eigen::VectorXd>& x, const std::vector<Eigen::MatrixXd>& P,
                      int sensor) {
  AlignedTracks a;
  a.sensor = sensor;
  a.dim = kD;
  a.n_times = static_cast<int32_t>(x.size());
  a.track = {0};
  a.truth = {0};
  for (int32_t k = 0; k < a.n_times; ++k) {
    a.times.push_back(kT * k);
    for (int c = 0; c < kD; ++c) a.state.push_back(x[k](c));
    for (int i = 0; i < kD; ++i)
      for (int j = i; j < kD; ++j) a.cov.push_back(P[k](i, j));
    a.valid.push_back(1);
  }
  a.span_begin = {0};  // the track over every scan
  a.span_offset = {0, a.n_times};
  return a;
}

Eigen::MatrixXd gain_at(const std::vector<double>& g, int32_t k) {
  Eigen::MatrixXd A(kD, kD);
  for (int i = 0; i < kD; ++i)
    for (int j = 0; j < kD; ++j) A(i, j) = g[(static_cast<std::size_t>(k) * kD + i) * kD + j];
  return A;
}

TEST(CrossCovariance, GainReadOffTheReportedCovariancesIsTheFiltersOwn) {
  std::mt19937_64 rng(11);
  const TwoFilterRun r = run_two_filters(rng, 12);
  const AlignedTracks a = aligned(r.xa, r.Pa, 0);
  const std::vector<double> g = gain_complements(a, kSigmaA);
  for (int32_t k = 0; k <= 12; ++k)
    EXPECT_LE((gain_at(g, k) - r.Aa[k]).norm(), 1e-8 * (1.0 + r.Aa[k].norm())) << "k " << k;
}

// E[e_a e_bᵀ] over 4000 runs against the recursion P_ab(k) = A_a(F P_ab Fᵀ + Q)A_bᵀ from P_ab(0) = 0.
TEST(CrossCovariance, RecursionEqualsTheMonteCarloCrossCovariance) {
  constexpr int kRuns = 4000, kSteps = 15;
  std::mt19937_64 rng(5);
  std::vector<Eigen::MatrixXd> empirical(kSteps + 1, Eigen::MatrixXd::Zero(kD, kD));
  TwoFilterRun last;
  for (int run = 0; run < kRuns; ++run) {
    last = run_two_filters(rng, kSteps);  // the covariances and gains do not depend on the run
    for (int k = 0; k <= kSteps; ++k)
      empirical[k] += (last.xa[k] - last.truth[k]) * (last.xb[k] - last.truth[k]).transpose() / kRuns;
  }
  const std::vector<double> ga = gain_complements(aligned(last.xa, last.Pa, 0), kSigmaA),
                            gb = gain_complements(aligned(last.xb, last.Pb, 1), kSigmaA);
  Eigen::MatrixXd F, Q;
  cv_transition(kD, kT, kSigmaA, F, Q);
  Eigen::MatrixXd Pab = Eigen::MatrixXd::Zero(kD, kD);
  double largest_correlation = 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    Pab = gain_at(ga, k) * (F * Pab * F.transpose() + Q) * gain_at(gb, k).transpose();
    for (int i = 0; i < kD; ++i) {
      const double scale = std::sqrt(last.Pa[k](i, i) * last.Pb[k](i, i));
      largest_correlation = std::max(largest_correlation, Pab(i, i) / scale);
      // Standard error of a sample cross-covariance ≈ scale/√runs: allow 5 of them.
      EXPECT_NEAR(empirical[k](i, i), Pab(i, i), 5.0 * scale / std::sqrt(kRuns)) << "k " << k << " i " << i;
    }
  }
  EXPECT_GT(largest_correlation, 0.2);  // the case is one where the correlation matters
}

// Each scan term of the statistic with common_process_noise is dᵀ(P_a + P_b − P_ab − P_ba)⁻¹d, with
// P_ab from the filters' true gains.
TEST(CrossCovariance, ScanTermsUseTheBarShalomCampoCovariance) {
  std::mt19937_64 rng(3);
  const TwoFilterRun r = run_two_filters(rng, 10);
  const AlignedTracks a = aligned(r.xa, r.Pa, 0), b = aligned(r.xb, r.Pb, 1);
  StatisticOptions opt;
  opt.common_process_noise = kSigmaA;
  const std::vector<double> terms = scan_terms(a, 0, b, 0, opt);
  opt.common_process_noise = 0.0;
  const std::vector<double> independent = scan_terms(a, 0, b, 0, opt);
  Eigen::MatrixXd F, Q;
  cv_transition(kD, kT, kSigmaA, F, Q);
  Eigen::MatrixXd Pab = Eigen::MatrixXd::Zero(kD, kD);
  int differ = 0;
  for (int k = 0; k <= 10; ++k) {
    if (k > 0) Pab = r.Aa[k] * (F * Pab * F.transpose() + Q) * r.Ab[k].transpose();
    const Eigen::VectorXd d = r.xa[k] - r.xb[k];
    const Eigen::MatrixXd C = r.Pa[k] + r.Pb[k] - Pab - Pab.transpose();
    const double expected = d.dot(C.ldlt().solve(d));
    EXPECT_NEAR(terms[k], expected, 1e-7 * (1.0 + expected)) << "k " << k;
    differ += std::abs(terms[k] - independent[k]) > 1e-3 * (1.0 + independent[k]);
  }
  EXPECT_GE(differ, 8);  // after the start, the correlated form is a different statistic
  StatisticOptions both;
  both.common_process_noise = 1.0;
  both.correlated = true;
  both.cross_correlation = 0.3;
  EXPECT_THROW(both.validate(), InputError);
}

using testing_support::CliFixture;
using testing_support::CliResult;
class Seed000Study : public CliFixture {};

// The study scores what users get: each row equals the same run through the command line.
TEST_F(Seed000Study, RowsEqualSimulateAssociateEvaluate) {
  Seed000ExperimentOptions o;
  o.targets = {8};
  o.runs = 2;
  o.seed = 4;
  o.solvers = {"hopfield", "lr"};
  o.output = path("seed000.h5");
  o.plot = "";
  const std::vector<Seed000Row> rows = run_seed000_experiment(o, nullptr);
  ASSERT_EQ(rows.size(), 1u * 2u * 2u * 2u * 2u);
  int checked = 0;
  for (const Seed000Row& row : rows) {
    SCOPED_TRACE(row.solver + " " + row.form + (row.correlated ? " correlated" : " independent") + " run " +
                 std::to_string(row.run));
    const std::string scenario =
        write("scenario.json", scenario_to_json(seed000_scenario(o, row.targets, row.correlated)));
    ASSERT_EQ(run("simulate --scenario " + scenario + " --seed 4 --run " + std::to_string(row.run) +
                  " --output " + path("sim.h5"))
                  .status,
              0);
    std::string flags =
        " --3d --alignment forward --process-noise 1 --gate-method chi2-sum --common-span intersection"
        " --cost-form " +
        row.form;
    if (row.correlated) flags += " --common-process-noise " + std::to_string(o.process_noise);
    const CliResult a =
        run("associate --input " + path("sim.h5") + " --output " + path("a.h5") + " --solver " + row.solver +
            " --seed " + std::to_string(o.seed + row.run) + flags);
    ASSERT_EQ(a.status, 0) << a.err;
    const CliResult e = run("evaluate --input " + path("a.h5") + " --output " + path("s.h5"));
    ASSERT_EQ(e.status, 0) << e.err;
    const TrackFile f = read_track_file(path("s.h5"));
    ASSERT_EQ(f.metrics.size(), 1u);
    EXPECT_DOUBLE_EQ(f.metrics[0].correct_rate, row.correct_rate);
    EXPECT_DOUBLE_EQ(f.metrics[0].false_rate, row.false_rate);
    ++checked;
  }
  EXPECT_EQ(checked, 16);
}

// Seed 004's solvers as `associate --sd` options (engine/studies/seed004/experiment_seed004.cpp).
std::string seed004_cli_solver(const std::string& solver) {
  if (solver == "chnn-eq12") return "chnn-pseudo --options '{\"gated\":true}'";
  if (solver == "chnn-eq7") return "chnn-pseudo --options '{\"gated\":false}'";
  if (solver == "chnn-eq12-single") return "chnn-pseudo --options '{\"gated\":true,\"leftover_passes\":0}'";
  if (solver == "exact") return "exact --options '{\"time_limit_s\":5}'";
  return solver;
}

TEST_F(Seed000Study, Seed004RowsEqualAssociateSdEvaluate) {
  Seed004ExperimentOptions o;
  o.scenarios = {"seed004"};
  o.runs = 2;
  o.seed = 3;
  o.solvers = {"chnn-eq12-single", "chnn-eq12", "chnn-eq7", "lr+ls", "exact"};
  const std::vector<Seed004Row> rows = run_seed004_experiment(o, nullptr);
  ASSERT_EQ(rows.size(), 2u * 5u);
  for (const Seed004Row& row : rows) {
    SCOPED_TRACE(row.solver + " run " + std::to_string(row.run));
    const Scenario sc = load_scenario("seed004");
    TrackFile file = simulation_to_track_file(sc, simulate(sc, o.seed, row.run));
    drop_sensor_target_tracks(file, o.p_miss, o.seed, row.run);
    write_track_file(path("in.h5"), file);
    const CliResult a =
        run("associate --sd --input " + path("in.h5") + " --output " + path("a.h5") + " --seed " +
            std::to_string(o.seed + row.run) + " --solver " + seed004_cli_solver(row.solver) +
            " --alignment forward --process-noise 1 --gate-method chi2-sum --common-span "
            "intersection --cost-form chain --link-cost per-independent-scan");
    ASSERT_EQ(a.status, 0) << a.err;
    ASSERT_EQ(run("evaluate --input " + path("a.h5") + " --output " + path("s.h5")).status, 0);
    const TrackFile f = read_track_file(path("s.h5"));
    ASSERT_EQ(f.metrics.size(), 1u);
    EXPECT_DOUBLE_EQ(f.metrics[0].correct_rate, row.correct_rate);
  }
}

TEST_F(Seed000Study, Seed001RatesEqualAssociateFuzzyEvaluate) {
  const CliResult x = run("experiment seed001 --runs 1 --output " + path("e.h5"));
  ASSERT_EQ(x.status, 0) << x.err;
  const TrackFile study = read_track_file(path("e.h5"));
  int compared = 0;
  for (const char* method : {"fuzzy", "ftaa"}) {
    SCOPED_TRACE(method);
    std::string options;
    for (const auto& a : study.associations)
      if (a.name == method) options = a.options_json;
    double study_rate = -1.0;
    for (const auto& m : study.metrics)
      if (m.name == std::string("seed001_") + method) study_rate = m.correct_rate;
    ASSERT_FALSE(options.empty());
    ASSERT_GE(study_rate, 0.0);
    const CliResult a = run("associate --input " + path("e.h5") + " --output " + path("a.h5") + " --solver " +
                            method + " --name again --options '" + options + "'");
    ASSERT_EQ(a.status, 0) << a.err;
    ASSERT_EQ(run("evaluate --input " + path("a.h5") + " --output " + path("s.h5")).status, 0);
    const TrackFile f = read_track_file(path("s.h5"));
    for (const auto& m : f.metrics)
      if (m.name == "again") {
        EXPECT_DOUBLE_EQ(m.correct_rate, study_rate);
        ++compared;
      }
  }
  EXPECT_EQ(compared, 2);
}

// A seed 003 scene as a track file: one row per plot, the position as the state, truth = target.
TrackFile scene_track_file(const Seed003Scene& sc) {
  TrackFile f;
  for (int s = 0; s < 2; ++s) {
    Sensor sensor;
    sensor.id = s;
    f.sensors.push_back(sensor);
    const TrackSequences& q = s == 0 ? sc.radar1 : sc.radar2;
    const std::vector<int32_t>& target = s == 0 ? sc.target1 : sc.target2;
    for (int32_t k = 0; k < q.size(); ++k)
      for (int64_t p = q.offset[k]; p < q.offset[k + 1]; ++p) {
        Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
        x << q.x[p], q.y[p], 0.0, 0.0;
        f.tracks.push_back(s, k, q.t[p], x, Eigen::MatrixXd::Identity(4, 4), target[k]);
      }
  }
  return f;
}

TEST(Seed003Study, TtcsnRateEqualsAssociateSiameseEvaluate) {
  const LoadedSiameseModel loaded =
      read_siamese_model(std::string(TRACKASSOC_SOURCE_DIR) + "/data/models/siamese_seed003.h5");
  Seed003ExperimentOptions o;
  o.densities = {10, 40};
  o.runs = 2;
  const Seed003ExperimentResult r = run_seed003_experiment(loaded.model, o);
  ASSERT_EQ(r.methods[0].method, "ttcsn");
  Seed003Options scenario = o.scenario;
  scenario.seed = o.seed;
  int imperfect = 0;
  for (std::size_t d = 0; d < o.densities.size(); ++d)
    for (int run = 0; run < o.runs; ++run) {
      const Seed003Scene sc =
          simulate_seed003_scene(scenario, o.densities[d], static_cast<uint64_t>(d) * 100000 + run);
      const TrackFile file = scene_track_file(sc);
      SiameseTrackFileOptions so;
      so.association.probability_threshold = o.probability_threshold;
      const SiameseTrackFileResult res = associate_siamese_tracks(file, loaded.model, so, "siamese");
      const double rate = evaluate_association(file.tracks, file.sensors, res.record).correct_rate;
      EXPECT_DOUBLE_EQ(rate, r.methods[0].accuracy[d][run]) << "density " << o.densities[d] << " run " << run;
      // and the classical baselines are scored by the same rule: a share in [0, 1]
      for (const auto& m : r.methods) imperfect += m.accuracy[d][run] < 1.0;
    }
  EXPECT_GT(imperfect, 0);  // the comparison is not between two trivial 100 % scores everywhere
}

}  // namespace
}  // namespace trackassoc
