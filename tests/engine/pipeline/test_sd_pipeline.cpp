// The S-D pipeline (engine/pipeline/pipeline_sd.hpp) and seed 004's CHNN with pseudo-tracks
// (kernels/hopfield/chnn_pseudo.hpp): pseudo-track costs by hand (Eq. 7, 9, 12), the network on a clear
// instance, determinism, S = 4 simulated tracks against brute force, a target seen by 3 of 4
// sensors, and the `associate --sd` CLI with its errors.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <set>

#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/seed004/experiment_seed004.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/chnn_pseudo.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;
constexpr double kInf = std::numeric_limits<double>::infinity();

PseudoTrackInput two_sensor_input() {
  PseudoTrackInput in;
  in.n = {2, 3};
  in.distance.assign(4, {});
  in.pseudo_cost.assign(4, 1.0);
  in.distance[PseudoTrackInput::pair(0, 1, 2)] = {1, 9, kInf, kInf, 2, 4};
  in.pseudo_cost[PseudoTrackInput::pair(0, 1, 2)] = 5.0;
  return in;
}

TEST(PseudoTracks, TwoSensorCostsFollowEq7) {
  // Sensor B's extended indices: 0, 1 = copies of A's tracks 0, 1; 2, 3, 4 = B's own tracks.
  const PseudoNeurons net = enumerate_pseudo_neurons(two_sensor_input());
  ASSERT_EQ(net.size(), 6u);  // row 0: its copy, B0, B1; row 1: its copy, B1, B2
  std::map<std::pair<int32_t, int32_t>, double> cost;
  for (std::size_t k = 0; k < net.size(); ++k) cost[{net.idx[2 * k], net.idx[2 * k + 1]}] = net.cost[k];
  EXPECT_EQ(cost.at({0, 0}), 5.0);    // A0 with its own pseudo-track: λ
  EXPECT_EQ(cost.at({0, 2}), 1.0);    // A0–B0: d
  EXPECT_EQ(cost.at({0, 3}), 9.0);    // A0–B1: d
  EXPECT_EQ(cost.count({0, 4}), 0u);  // A0–B2 outside the gate (+inf): no neuron (Eq. 12)
  EXPECT_EQ(cost.count({0, 1}), 0u);  // A0 with A1's pseudo-track: +inf
  EXPECT_EQ(cost.at({1, 1}), 5.0);
  EXPECT_EQ(cost.count({1, 2}), 0u);
  EXPECT_EQ(cost.at({1, 3}), 2.0);
  EXPECT_EQ(cost.at({1, 4}), 4.0);
  EXPECT_EQ(cost.count({1, 0}), 0u);
  EXPECT_EQ(net.stands_for[1][0], (std::pair<int32_t, int32_t>{0, 0}));
  EXPECT_EQ(net.stands_for[1][3], (std::pair<int32_t, int32_t>{1, 1}));
}

TEST(PseudoTracks, ThreeSensorChainCostIsEq9) {
  PseudoTrackInput in;
  in.n = {1, 1, 1};
  in.distance.assign(9, {});
  in.pseudo_cost.assign(9, 1.0);
  in.distance[PseudoTrackInput::pair(0, 1, 3)] = {2};
  in.distance[PseudoTrackInput::pair(1, 2, 3)] = {3};
  in.distance[PseudoTrackInput::pair(0, 2, 3)] = {4};
  in.pseudo_cost[PseudoTrackInput::pair(0, 1, 3)] = 5;
  in.pseudo_cost[PseudoTrackInput::pair(0, 2, 3)] = 6;
  in.pseudo_cost[PseudoTrackInput::pair(1, 2, 3)] = 7;
  const PseudoNeurons net = enumerate_pseudo_neurons(in);
  // C's extended indices: 0 = copy of A0, 1 = copy of B0, 2 = C0. B's: 0 = copy of A0, 1 = B0.
  std::map<std::vector<int32_t>, double> cost;
  for (std::size_t k = 0; k < net.size(); ++k)
    cost[{net.idx[3 * k], net.idx[3 * k + 1], net.idx[3 * k + 2]}] = net.cost[k];
  ASSERT_EQ(cost.size(), 4u);
  EXPECT_EQ(cost.at({0, 0, 0}), 5.0 + 6.0);  // A0 alone: λ_AB + λ_AC
  EXPECT_EQ(cost.at({0, 0, 2}), 5.0 + 4.0);  // A0–C0, no B: λ_AB + d_AC
  EXPECT_EQ(cost.at({0, 1, 1}), 2.0 + 7.0);  // A0–B0, no C: d_AB + λ_BC
  EXPECT_EQ(cost.at({0, 1, 2}), 2.0 + 3.0);  // A0–B0–C0: d_AB + d_BC (Eq. 9)
}

TEST(PseudoTracks, NetworkGroupsAClearInstance) {
  // Targets 0, 1, 2 seen by A and C; B sees 0 and 1 only. True pairs at distance 1, others gated.
  PseudoTrackInput in;
  in.n = {3, 2, 3};
  in.distance.assign(9, {});
  in.pseudo_cost.assign(9, 5.0);
  auto diag = [](int32_t a, int32_t b) {
    std::vector<double> d(static_cast<std::size_t>(a) * b, kInf);
    for (int32_t i = 0; i < std::min(a, b); ++i) d[static_cast<std::size_t>(i) * b + i] = 1.0;
    return d;
  };
  in.distance[PseudoTrackInput::pair(0, 1, 3)] = diag(3, 2);
  in.distance[PseudoTrackInput::pair(0, 2, 3)] = diag(3, 3);
  in.distance[PseudoTrackInput::pair(1, 2, 3)] = diag(2, 3);
  const ChnnPseudoResult r = solve_chnn_pseudo(in);
  EXPECT_TRUE(r.converged);
  std::set<std::vector<int32_t>> got;
  for (std::size_t k = 0; k < r.solution.tuples.size(); k += 3)
    got.insert({r.solution.tuples[k], r.solution.tuples[k + 1], r.solution.tuples[k + 2]});
  EXPECT_EQ(got, (std::set<std::vector<int32_t>>{{0, 0, 0}, {1, 1, 1}, {2, kNoTrack, 2}}));
}

TEST(PseudoTracks, LeftoverPassGroupsTargetsTheReferenceMissed) {
  // A sees target 0 only; B and C see targets 0 and 1 (B1–C1 at distance 1).
  PseudoTrackInput in;
  in.n = {1, 2, 2};
  in.distance.assign(9, {});
  in.pseudo_cost.assign(9, 5.0);
  in.distance[PseudoTrackInput::pair(0, 1, 3)] = {1, kInf};
  in.distance[PseudoTrackInput::pair(0, 2, 3)] = {1, kInf};
  in.distance[PseudoTrackInput::pair(1, 2, 3)] = {1, kInf, kInf, 1};
  auto tuples = [&](int passes) {
    ChnnPseudoOptions o;
    o.leftover_passes = passes;
    const ChnnPseudoResult r = solve_chnn_pseudo(in, o);
    std::set<std::vector<int32_t>> got;
    for (std::size_t k = 0; k < r.solution.tuples.size(); k += 3)
      got.insert({r.solution.tuples[k], r.solution.tuples[k + 1], r.solution.tuples[k + 2]});
    return got;
  };
  // The paper's single pass leaves B1 and C1 alone; the leftover pass groups them.
  EXPECT_EQ(tuples(0),
            (std::set<std::vector<int32_t>>{{0, 0, 0}, {kNoTrack, 1, kNoTrack}, {kNoTrack, kNoTrack, 1}}));
  EXPECT_EQ(tuples(-1), (std::set<std::vector<int32_t>>{{0, 0, 0}, {kNoTrack, 1, 1}}));
}

TEST(PseudoTracks, BitIdenticalForOneAndTwoThreads) {
  PseudoTrackInput in;
  in.n = {12, 11, 12, 10};
  const int32_t S = 4;
  in.distance.assign(S * S, {});
  in.pseudo_cost.assign(S * S, 30.0);
  CounterRng rng(3, 0, 0);
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      auto& d = in.distance[PseudoTrackInput::pair(a, b, S)];
      d.resize(static_cast<std::size_t>(in.n[a]) * in.n[b]);
      for (double& x : d) x = rng.uniform() < 0.3 ? rng.uniform(0.0, 40.0) : kInf;
    }
  ChnnPseudoResult one, two;
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
    one = solve_chnn_pseudo(in);
  }
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
    two = solve_chnn_pseudo(in);
  }
  EXPECT_EQ(one.solution.tuples, two.solution.tuples);
  EXPECT_EQ(one.steps, two.steps);
}

TEST(PseudoTracks, BadInputIsRejected) {
  PseudoTrackInput in = two_sensor_input();
  in.pseudo_cost[PseudoTrackInput::pair(0, 1, 2)] = 0.0;
  EXPECT_THROW(in.validate(), InputError);
  in = two_sensor_input();
  in.distance[PseudoTrackInput::pair(0, 1, 2)][0] = -1.0;
  EXPECT_THROW(in.validate(), InputError);
  ChnnPseudoOptions o;
  o.u0 = 0.0;
  EXPECT_THROW(o.validate(), InputError);
}

// Four asynchronous 3-D sensors, the first `targets` targets of the seed 004 scenario, 80 s.
TrackFile four_sensor_file(int32_t targets) {
  Scenario sc = load_scenario("seed004");
  sc.targets.resize(targets);
  sc.duration = 80.0;
  return simulation_to_track_file(sc, simulate(sc, 1, 0));
}

TEST(SDPipeline, FourSensorsAgainstBruteForce) {
  const TrackFile file = four_sensor_file(3);
  const SDProblem p = build_sd_problem(file, PipelineOptions{});
  ASSERT_EQ(p.S(), 4);
  const double optimum = brute_force_sd(p.tensor);
  for (const std::string solver : {"lr+ls", "exact"}) {
    SCOPED_TRACE(solver);
    const SolutionSD s = solve_sd(p, solver, nlohmann::json::object(), 1);
    EXPECT_TRUE(is_valid_assignment_sd(p.tensor, s.tuples));
    EXPECT_NEAR(s.summary.objective, optimum, 1e-3 * std::max(1.0, std::abs(optimum)));
    EXPECT_LE(s.summary.lower_bound, optimum + 1e-3 * std::max(1.0, std::abs(optimum)));
    const AssociationRecord rec =
        solve_sd_association(p, solver, nlohmann::json::object(), 1, PipelineOptions{});
    EXPECT_EQ(rec.num_sensors, 4);
    EXPECT_DOUBLE_EQ(evaluate_association(file.tracks, file.sensors, rec).correct_rate, 1.0);
  }
}

TEST(SDPipeline, TargetSeenByThreeOfFourSensorsIsCorrectWhenGrouped) {
  TrackFile file = four_sensor_file(5);
  // Remove sensor 2's track of target 3 (and only that one).
  TrackTable kept(file.tracks.layout);
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    if (!(file.tracks.sensor[r] == 2 && file.tracks.truth[r] == 3))
      kept.push_back(file.tracks.sensor[r], file.tracks.track[r], file.tracks.t[r], file.tracks.state_at(r),
                     file.tracks.cov_at(r), file.tracks.truth[r]);
  file.tracks = kept;
  const SDProblem p = build_sd_problem(file, PipelineOptions{});
  EXPECT_EQ(p.aligned[2].n_tracks(), 4);
  for (const std::string solver : {"lr+ls", "chnn-pseudo"}) {
    SCOPED_TRACE(solver);
    const AssociationRecord rec =
        solve_sd_association(p, solver, nlohmann::json::object(), 1, PipelineOptions{});
    const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
    EXPECT_EQ(m.targets, 5);
    EXPECT_EQ(m.correct, 5);
    // Exactly one output tuple has a dummy in sensor 2's column, and it holds target 3's tracks.
    int32_t with_dummy = 0;
    for (std::size_t k = 0; k < rec.num_tuples(); ++k) with_dummy += rec.tuples[k * 4 + 2] == kNoTrack;
    EXPECT_EQ(with_dummy, 1);
  }
}

TEST(SDPipeline, DropSensorTargetTracksIsDeterministic) {
  TrackFile a = four_sensor_file(5), b = four_sensor_file(5);
  const int32_t da = drop_sensor_target_tracks(a, 0.3, 7, 2), db = drop_sensor_target_tracks(b, 0.3, 7, 2);
  EXPECT_EQ(da, db);
  EXPECT_GT(da, 0);
  EXPECT_EQ(a.tracks.t, b.tracks.t);
}

TEST(SDPipeline, BadOptionsAreRejected) {
  const TrackFile file = four_sensor_file(2);
  PipelineOptions o;
  o.statistic.gate_probability = 1.0;
  EXPECT_THROW(build_sd_problem(file, o), InputError);
  o = {};
  o.sensors = {0, 1, 9};
  EXPECT_THROW(build_sd_problem(file, o), InputError);
  o.sensors = {0, 0, 1};
  EXPECT_THROW(build_sd_problem(file, o), InputError);
  const SDProblem p = build_sd_problem(file, PipelineOptions{});
  EXPECT_THROW(solve_sd(p, "hopfield", nlohmann::json::object(), 1), InputError);
  EXPECT_THROW(solve_sd(p, "chnn-pseudo", {{"gated", 3}}, 1), InputError);
  EXPECT_THROW(solve_sd(p, "lr", {{"bogus", 1}}, 1), InputError);
}

class SDCli : public CliFixture {};

TEST_F(SDCli, AssociateSdWritesFourColumnTuplesAndRejectsBadSolvers) {
  const std::string sim = path("sim.h5"), out = path("out.h5");
  ASSERT_EQ(run("simulate --scenario seed004 --output " + sim).status, 0);
  CliResult r = run("associate --input " + sim + " --output " + out + " --sd --solver lr+ls");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("4 sensors (S-D)"), std::string::npos) << r.out;
  const TrackFile f = read_track_file(out);
  ASSERT_EQ(f.associations.size(), 1u);
  EXPECT_EQ(f.associations[0].num_sensors, 4);
  EXPECT_TRUE(std::isfinite(f.associations[0].lower_bound));
  r = run("evaluate --input " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("100.0 %"), std::string::npos) << r.out;
  // Four --sensors imply the S-D formulation.
  r = run("associate --input " + sim + " --output " + path("o2.h5") +
          " --sensors 0 1 2 3 --solver chnn-pseudo");
  EXPECT_EQ(r.status, 0) << r.err;
  r = run("associate --input " + sim + " --output " + path("o3.h5") + " --sd --solver hopfield");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not an S-D solver"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("o3.h5")));
  r = run("associate --input " + sim + " --output " + path("o4.h5") + " --sd --solver lr --gate 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("gate"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace trackassoc
