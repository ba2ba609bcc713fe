// The `trackassoc` binary end to end: the main job, exit statuses, one-line errors, and that bad
// input never leaves an output file behind (DESIGN §2 Errors, §7).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/track_file.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string out, err;
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trackassoc_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::string& args) {
    const std::string out = (dir_ / "stdout.txt").string(), err = (dir_ / "stderr.txt").string();
    const std::string cmd = std::string(TRACKASSOC_CLI) + " " + args + " >" + out + " 2>" + err;
    const int raw = std::system(cmd.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

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
  for (const auto& m : file.metrics) {
    EXPECT_GE(m.correct_rate, 0.0);
    EXPECT_NEAR(m.correct_rate + m.false_rate + m.missed_rate, 1.0, 1e-12);
  }
}

TEST_F(CliTest, SimulateAssociateEvaluate) {
  ASSERT_EQ(run("simulate --output " + path("sim.h5")).status, 0);
  const Result a =
      run("associate --input " + path("sim.h5") + " --output " + path("assoc.h5") + " --solver greedy");
  ASSERT_EQ(a.status, 0) << a.err;
  const Result e = run("evaluate --input " + path("assoc.h5"));
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_NE(e.out.find("greedy"), std::string::npos);
  const auto file = trackassoc::read_track_file(path("assoc.h5"));
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
