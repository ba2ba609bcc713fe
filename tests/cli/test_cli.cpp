// The `trackassoc` binary end to end: the main job, exit statuses, one-line errors, and that bad
// input never leaves an output file behind (docs/design.md §2 Errors, §7).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace fs = std::filesystem;

namespace {

using Result = trackassoc::testing_support::CliResult;
class CliTest : public trackassoc::testing_support::CliFixture {};

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST_F(CliTest, RunPrintsATableAndWritesAReadableFile) {
  const Result r = run("run --threads 2 --output " + path("run.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("correct"), std::string::npos);
  EXPECT_NE(r.out.find("pairwise"), std::string::npos);
  const auto file = trackassoc::read_track_file(path("run.h5"));
  EXPECT_GE(file.associations.size(), 2u);
  EXPECT_EQ(file.metrics.size(), file.associations.size());
  // The run scores as `evaluate` does: scoring its file again gives the same rates.
  ASSERT_EQ(run("evaluate --input " + path("run.h5") + " --output " + path("again.h5")).status, 0);
  const auto again = trackassoc::read_track_file(path("again.h5"));
  ASSERT_EQ(again.metrics.size(), file.metrics.size());
  for (std::size_t k = 0; k < file.metrics.size(); ++k) {
    EXPECT_EQ(again.metrics[k].name, file.metrics[k].name);
    EXPECT_EQ(again.metrics[k].correct_rate, file.metrics[k].correct_rate) << file.metrics[k].name;
    EXPECT_EQ(again.metrics[k].false_rate, file.metrics[k].false_rate) << file.metrics[k].name;
    EXPECT_EQ(again.metrics[k].missed_rate, file.metrics[k].missed_rate) << file.metrics[k].name;
  }
}

// `evaluate` on a hand-made file: sensors 10, 20, 30; local track k of every sensor follows target
// 100 + k. "swap" exchanges sensor 30's tracks of targets 101 and 102 (both false, 100 correct);
// "split" leaves target 102's sensor-30 track alone (missed, the others correct).
TEST_F(CliTest, EvaluateWritesTheHandCountedRates) {
  trackassoc::TrackFile f;
  f.sensors.resize(3);
  for (int s = 0; s < 3; ++s) f.sensors[s].id = 10 * (s + 1);
  f.tracks = trackassoc::TrackTable(trackassoc::StateLayout::kXY_VXVY);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
  for (int s = 0; s < 3; ++s)
    for (int32_t k = 0; k < 3; ++k)
      for (double t : {0.0, 1.0}) f.tracks.push_back(10 * (s + 1), k, t, x, P, 100 + k);
  auto record = [](const std::string& name, std::vector<int32_t> tuples) {
    trackassoc::AssociationRecord r;
    r.name = name;
    r.solver = "hand";
    r.num_sensors = 3;
    r.tuples = std::move(tuples);
    r.cost.assign(r.tuples.size() / 3, 0.0);
    return r;
  };
  f.associations = {record("swap", {0, 0, 0, 1, 1, 2, 2, 2, 1}),
                    record("split", {0, 0, 0, 1, 1, 1, 2, 2, -1, -1, -1, 2})};
  trackassoc::write_track_file(path("hand.h5"), f);
  const Result r = run("evaluate --input " + path("hand.h5") + " --output " + path("scored.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("66.7 %"), std::string::npos) << r.out;
  const auto scored = trackassoc::read_track_file(path("scored.h5"));
  ASSERT_EQ(scored.metrics.size(), 2u);
  const double third = 1.0 / 3.0;
  for (const auto& m : scored.metrics) {
    SCOPED_TRACE(m.name);
    const bool swap = m.name == "swap";
    EXPECT_NEAR(m.correct_rate, swap ? third : 2 * third, 1e-15);
    EXPECT_NEAR(m.false_rate, swap ? 2 * third : 0.0, 1e-15);
    EXPECT_NEAR(m.missed_rate, swap ? 0.0 : third, 1e-15);
    // Pairs (engine/pipeline/pair_metrics.hpp): every track spans [0, 1], so each target's 3 tracks
    // make 3 coexisting pairs, 9 in all. swap: target 100 keeps its 3, 101 and 102 one each (their
    // sensor-10/20 pair) -> 5 of 9 linked; its 3 tuples link 9 pairs, 5 of one target. split: 3 + 3
    // + 1 linked, all 7 linked pairs right. No target has two tracks on one sensor: no fragments.
    EXPECT_EQ(m.tables.at("n_coexisting_pairs"), std::vector<double>{9.0});
    EXPECT_EQ(m.tables.at("n_coexisting_linked"), std::vector<double>{swap ? 5.0 : 7.0});
    EXPECT_EQ(m.tables.at("n_linked_pairs"), std::vector<double>{swap ? 9.0 : 7.0});
    EXPECT_EQ(m.tables.at("n_linked_pairs_same_truth"), std::vector<double>{swap ? 5.0 : 7.0});
    EXPECT_EQ(m.tables.at("n_fragment_pairs"), std::vector<double>{0.0});
  }
  EXPECT_NE(r.out.find("55.56 % (5 of 9)"), std::string::npos)
      << r.out;  // swap's coexisting recall, precision
  EXPECT_NE(r.out.find("100.00 % (7 of 7)"), std::string::npos) << r.out;  // split's precision
}

TEST_F(CliTest, SimulateAssociateEvaluate) {
  ASSERT_EQ(run("simulate --output " + path("sim.h5")).status, 0);
  const Result a =
      run("associate --input " + path("sim.h5") + " --output " + path("assoc.h5") + " --solver greedy");
  ASSERT_EQ(a.status, 0) << a.err;
  // Without --output evaluate only prints: the input is left byte for byte as it was.
  const std::string before = slurp(path("assoc.h5"));
  const Result e = run("evaluate --input " + path("assoc.h5"));
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_NE(e.out.find("greedy"), std::string::npos);
  EXPECT_EQ(slurp(path("assoc.h5")), before);
  EXPECT_TRUE(trackassoc::read_track_file(path("assoc.h5")).metrics.empty());
  const Result o = run("evaluate --input " + path("assoc.h5") + " --output " + path("scored.h5"));
  ASSERT_EQ(o.status, 0) << o.err;
  const auto file = trackassoc::read_track_file(path("scored.h5"));
  ASSERT_EQ(file.metrics.size(), 1u);
  EXPECT_EQ(file.metrics[0].name, "greedy");
}

TEST_F(CliTest, RandomBytesInputGivesOneLineErrorExit2AndNoOutput) {
  {
    std::ofstream f(path("garbage.h5"), std::ios::binary);
    for (int i = 0; i < 4096; ++i) f.put(static_cast<char>((i * 2654435761u) >> 13));
  }
  const Result r = run("associate --input " + path("garbage.h5") + " --output " + path("out.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("garbage.h5"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_FALSE(fs::exists(path("out.h5.tmp")));
}

TEST_F(CliTest, MissingInputFile) {
  const Result r = run("evaluate --input " + path("nope.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
}

TEST_F(CliTest, UnknownSolverIsRejectedBeforeAnyWork) {
  ASSERT_EQ(run("simulate --output " + path("sim.h5")).status, 0);
  const Result r =
      run("associate --input " + path("sim.h5") + " --output " + path("o.h5") + " --solver magic");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown solver 'magic'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

TEST_F(CliTest, BadScenarioAndBadOptions) {
  {
    std::ofstream f(path("bad.json"));
    f << "{\"sensors\": 3, \"nonsense\": true}";
  }
  Result r = run("simulate --scenario " + path("bad.json") + " --output " + path("s.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(path("s.h5")));
  r = run("run --gate 1.5 --output " + path("r.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("gate"), std::string::npos) << r.err;
  r = run("run --options '{not json' --output " + path("r.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_FALSE(fs::exists(path("r.h5")));
}

TEST_F(CliTest, OutputIntoMissingFolderKeepsNothing) {
  const Result r = run("simulate --output " + path("no/such/dir/s.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
}

TEST_F(CliTest, SameSeedSameBytesForOneAndTwoThreads) {
  ASSERT_EQ(run("run --threads 1 --seed 7 --solvers greedy,pairwise --output " + path("t1.h5")).status, 0);
  ASSERT_EQ(run("run --threads 2 --seed 7 --solvers greedy,pairwise --output " + path("t2.h5")).status, 0);
  const auto a = trackassoc::read_track_file(path("t1.h5"));
  const auto b = trackassoc::read_track_file(path("t2.h5"));
  ASSERT_EQ(a.tracks.size(), b.tracks.size());
  for (std::size_t c = 0; c < a.tracks.state.size(); ++c) EXPECT_EQ(a.tracks.state[c], b.tracks.state[c]);
  ASSERT_EQ(a.associations.size(), b.associations.size());
  for (std::size_t i = 0; i < a.associations.size(); ++i) {
    EXPECT_EQ(a.associations[i].tuples, b.associations[i].tuples);
    EXPECT_EQ(a.associations[i].cost, b.associations[i].cost);
  }
}

}  // namespace

// `trackassoc solvers` lists every registry entry with its options (engine/solvers/solver_registry.hpp);
// an unknown name is exit 2 with a "did you mean".
TEST_F(CliTest, SolversListsTheRegistryWithItsOptions) {
  const auto all = run("solvers");
  ASSERT_EQ(all.status, 0) << all.err;
  for (const char* name : {"greedy", "pairwise", "lr", "lr+ls", "exact", "hopfield", "hopfield-paper", "chnn",
                           "greedy+ls", "chnn+ls", "chnn-pseudo"})
    EXPECT_NE(("\n" + all.out).find(std::string("\n") + name + ": "), std::string::npos) << name;
  const auto one = run("solvers hopfield");
  ASSERT_EQ(one.status, 0) << one.err;
  EXPECT_EQ(one.out.rfind("hopfield: ", 0), 0u) << one.out;
  EXPECT_NE(one.out.find("schedules sync, async, diagonal"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("  restarts "), std::string::npos) << one.out;
  EXPECT_EQ(one.out.find("hopfield-paper: "), std::string::npos);
  const auto bad = run("solvers hopfeld");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("did you mean 'hopfield'"), std::string::npos) << bad.err;
}
