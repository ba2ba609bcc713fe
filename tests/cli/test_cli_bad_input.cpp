// Issue 15, "Bad input, part 2": what a user who mistypes gets from the `trackassoc` binary.
// (4) Out-of-range numbers and misspelt keys were accepted silently with exit 0; they are usage
// errors now (exit 2, one line naming the option or key). (5) Messages that named the wrong cause.
// (6) A second, bad output path replaced the first output before failing; every output path is
// checked before any work. Each case is a user's command on a user's files.
#include <hdf5.h>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;
using testing_support::CliResult;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class BadInput : public CliFixture {
 protected:
  // A usage error: status 2, one line on stderr that contains every one of `parts`.
  void expect_refused(const CliResult& r, const std::vector<std::string>& parts) {
    EXPECT_EQ(r.status, 2) << r.err;
    for (const auto& p : parts) EXPECT_TRUE(has(r.err, p)) << "expected '" << p << "' in: " << r.err;
    EXPECT_FALSE(has(r.err, "internal error")) << r.err;
  }
  // A simulated seed000 track file with /measurements.
  std::string simulated(const std::string& name) {
    const CliResult r = run("simulate --output " + path(name));
    EXPECT_EQ(r.status, 0) << r.err;
    return path(name);
  }
};

// ---------------------------------------------------------------- (4) silently accepted

TEST_F(BadInput, SeedNegativeOrBeyond64BitsIsRefused) {
  for (const std::string seed : {"-1", "18446744073709551616", "99999999999999999999999", "1.5", "0x10"}) {
    const CliResult r = run("simulate --seed " + seed + " --output " + path("s.h5"));
    expect_refused(r, {"--seed", seed});
    EXPECT_FALSE(std::filesystem::exists(path("s.h5"))) << seed;
  }
  // 2^64 - 1 is a seed; "010" is ten (decimal), not eight (octal): the same file as --seed 10.
  EXPECT_EQ(run("simulate --seed 18446744073709551615 --output " + path("max.h5")).status, 0);
  ASSERT_EQ(run("simulate --seed 010 --output " + path("a.h5")).status, 0);
  ASSERT_EQ(run("simulate --seed 10 --output " + path("b.h5")).status, 0);
  ASSERT_EQ(run("simulate --seed 8 --output " + path("c.h5")).status, 0);
  const TrackFile a = read_track_file(path("a.h5")), b = read_track_file(path("b.h5")),
                  c = read_track_file(path("c.h5"));
  EXPECT_EQ(a.tracks.state[0], b.tracks.state[0]);
  EXPECT_NE(a.tracks.state[0], c.tracks.state[0]);
}

TEST_F(BadInput, NegativeCorrelationIsRefusedAndHelpStatesTheRange) {
  const std::string in = simulated("sim.h5");
  expect_refused(run("associate --input " + in + " --output " + path("o.h5") + " --correlated -0.5"),
                 {"--correlated", "[0, 1)", "-0.5"});
  expect_refused(run("associate --input " + in + " --output " + path("o.h5") + " --correlated 1"),
                 {"--correlated"});
  expect_refused(run("associate --input " + in + " --output " + path("o.h5") + " --gate nan"), {"--gate"});
  EXPECT_FALSE(std::filesystem::exists(path("o.h5")));
  EXPECT_EQ(run("associate --input " + in + " --output " + path("o.h5") + " --correlated 0.5").status, 0);
  const CliResult help = run("associate --help");
  EXPECT_TRUE(has(help.out, "in [0, 1)")) << help.out;       // --correlated
  EXPECT_TRUE(has(help.out, "in (0, 1]")) << help.out;       // --gate
  EXPECT_TRUE(has(help.out, "in [0, 2^64-1]")) << help.out;  // --seed
}

TEST_F(BadInput, FilterProcessNoiseMinusOneIsNotAHiddenDefault) {
  const std::string in = simulated("sim.h5");
  expect_refused(run("filter --input " + in + " --output " + path("f.h5") + " --process-noise -1"),
                 {"--process-noise", "-1"});
  EXPECT_FALSE(std::filesystem::exists(path("f.h5")));
}

TEST_F(BadInput, NegativePairLimitIsRefusedBeforeTheDataIsRead) {
  expect_refused(
      run("train-siamese --data " + path("none.h5") + " --output " + path("m.h5") + " --max-train-pairs -5"),
      {"--max-train-pairs", "-5"});
}

TEST_F(BadInput, MisspeltSolverNameInRunOptionsIsRefusedWithASuggestion) {
  const CliResult r =
      run("run --output " + path("r.h5") + " --no-plots --options '{\"hopfeld\": {\"restarts\": 2}}'");
  expect_refused(r, {"--options", "unknown solver 'hopfeld'", "did you mean 'hopfield'", "greedy"});
  EXPECT_FALSE(std::filesystem::exists(path("r.h5")));
  // Options for a solver that --solvers leaves out would be ignored as well.
  expect_refused(
      run("run --output " + path("r.h5") + " --no-plots --solvers greedy --options '{\"lr\": {}}'"),
      {"--options", "'lr'", "--solvers"});
}

TEST_F(BadInput, MisspeltKeyOfASolverIsRefusedBeforeAnyWork) {
  const CliResult r = run("run --output " + path("r.h5") + " --no-plots --solvers hopfield --options " +
                          "'{\"hopfield\": {\"restart\": 2}}'");
  expect_refused(
      r, {"solver 'hopfield' options", "unknown key 'restart'", "did you mean 'restarts'", "max_sweeps"});
  EXPECT_FALSE(std::filesystem::exists(path("r.h5")));
  expect_refused(run("run --output " + path("r.h5") + " --no-plots --solvers lr --options " +
                     "'{\"lr\": {\"max_iteration\": 5}}'"),
                 {"solver 'lr' options", "unknown key 'max_iteration'", "did you mean 'max_iterations'"});
}

// Row r of test::full_track_file (24 rows) is sensor 10 · (1 + r / 12), track 2 - (r / 4) % 3, at
// t = 2 · (r % 4): rows 0 and 1 are sensor 10, track 2 at t = 0 and t = 2. Setting row 1's t to 0
// makes them two reports of one track at one time.
TEST_F(BadInput, DuplicatedReportWithADifferentStateNamesBothRows) {
  const std::string in = path("dup.h5");
  write_track_file(in, test::full_track_file(StateLayout::kXY_VXVY));
  test::damage_file(in, [](hid_t f) {
    std::vector<double> t = test::read_all_doubles(f, "/tracks/t");
    t[1] = t[0];
    test::put_dataset(f, "/tracks/t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {t.size()}, t.data());
  });
  expect_refused(run("associate --input " + in + " --output " + path("o.h5")),
                 {in, "/tracks: row 1: sensor 10, track 2, t = 0 is also row 0 with a different state"});
  EXPECT_FALSE(std::filesystem::exists(path("o.h5")));
}

TEST_F(BadInput, RepeatedIdenticalReportIsAlsoNamed) {
  const std::string in = path("dup.h5");
  write_track_file(in, test::full_track_file(StateLayout::kXY_VXVY));
  test::damage_file(in, [](hid_t f) {
    for (const char* name : {"/tracks/t", "/tracks/state", "/tracks/cov"}) {
      std::vector<double> v = test::read_all_doubles(f, name);
      const std::size_t cols = v.size() / 24;  // 24 rows (two sensors, three tracks, four reports)
      std::copy(v.begin(), v.begin() + cols, v.begin() + cols);
      const std::vector<hsize_t> dims = cols == 1 ? std::vector<hsize_t>{24} : std::vector<hsize_t>{24, cols};
      test::put_dataset(f, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims, v.data());
    }
  });
  expect_refused(run("associate --input " + in + " --output " + path("o.h5")),
                 {"/tracks: row 1: sensor 10, track 2, t = 0 is also row 0 (the same state repeated)"});
}

// ---------------------------------------------------------------- (5) wrong exit or wrong words

TEST_F(BadInput, JsonNumberOutOfRangeInOptionsIsAnInputError) {
  const std::string instance = write("i.txt", "3\n2 2 2\n1 2 3 4 5 6 7 8\n");
  expect_refused(run("solve3d --instance " + instance + " --options '{\"max_iterations\": 1e400}'"),
                 {"--options", "number overflow"});
  expect_refused(
      run("solve3d --instance " + instance + " --solver lr --options '{\"max_iterations\": 5000000000}'"),
      {"solver 'lr' options", "'max_iterations'", "out of range"});
  expect_refused(run("solve3d --instance " + instance + " --solver hopfield --options '{\"A\": 1e300}'"),
                 {"solver 'hopfield' options", "'A'", "out of range"});
}

TEST_F(BadInput, ZeroSensorSigmaIsNamedNotTheTracksItWouldBreak) {
  const std::string in = simulated("sim.h5");
  test::damage_file(in, [](hid_t f) {
    std::vector<double> s = test::read_all_doubles(f, "/sensors/sigma_range");
    s[0] = 0.0;
    test::put_dataset(f, "/sensors/sigma_range", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {s.size()}, s.data());
  });
  const CliResult r = run("filter --input " + in + " --output " + path("f.h5"));
  expect_refused(r, {in + ": /sensors/sigma_range: row 0", "σ > 0"});
  EXPECT_FALSE(has(r.err, ".tmp")) << r.err;
  EXPECT_FALSE(has(r.err, "/tracks/cov")) << r.err;
}

TEST_F(BadInput, ScenarioWithoutATargetAreaIsExplained) {
  // random_targets without area_min/area_max: the area is the origin, where this sensor stands.
  const std::string sc = write("sc.json", R"({"name": "origin", "duration": 20, "sensors": [
      {"position": [0, 0]}, {"position": [50000, 0]}, {"position": [0, 50000]}],
      "random_targets": {"count": 4}})");
  const CliResult r = run("simulate --scenario " + sc + " --output " + path("s.h5"));
  expect_refused(r, {"random_targets.area_max", "single point", "area_min"});
  EXPECT_FALSE(has(r.err, "/tracks")) << r.err;
}

TEST_F(BadInput, TargetOnASensorIsExplainedAsTheScenario) {
  // A scripted target standing on sensor 0: its range measurements are clamped at 0.
  const std::string sc = write("sc.json", R"({"name": "on-sensor", "duration": 20, "sensors": [
      {"position": [0, 0]}, {"position": [50000, 0]}, {"position": [0, 50000]}],
      "targets": [{"position": [0, 0], "velocity": [0, 0]}]})");
  const CliResult r = run("simulate --scenario " + sc + " --output " + path("s.h5"));
  expect_refused(r, {"scenario 'on-sensor'", "target 0 comes within 0", "of sensor 0"});
  EXPECT_FALSE(has(r.err, ".tmp")) << r.err;
}

TEST_F(BadInput, InstanceThatIsADirectoryIsCalledOne) {
  std::filesystem::create_directories(path("folder"));
  expect_refused(run("solve3d --instance " + path("folder")), {"--instance", "is a directory"});
}

TEST_F(BadInput, TrainSiameseChecksItsOptionsBeforeTheDataAndPrintsNothingFirst) {
  // No such data file: the bad option is reported, not the file, and no "training ..." line.
  const CliResult r =
      run("train-siamese --data " + path("none.h5") + " --output " + path("m.h5") + " --hidden 0");
  expect_refused(r, {"--hidden"});
  EXPECT_FALSE(has(r.err, "none.h5")) << r.err;
  EXPECT_FALSE(has(r.err, "training")) << r.err;
  // An output folder that does not exist is found before the data is read, too.
  const CliResult o = run("train-siamese --data " + path("none.h5") + " --output " + path("nodir/m.h5"));
  expect_refused(o, {"--output", "nodir", "does not exist"});
}

// ---------------------------------------------------------------- (6) lost output

TEST_F(BadInput, BadPlotPathLeavesTheExistingOutputAlone) {
  const std::string out = write("out.h5", "the previous results");
  const CliResult r =
      run("experiment seed000 --runs 1 --targets 3 --output " + out + " --plots " + path("nodir/e.svg"));
  expect_refused(r, {"--plots", "nodir", "does not exist"});
  EXPECT_EQ(slurp(out), "the previous results");
  const CliResult run_plot = run("run --output " + out + " --plots " + path("nodir/r.svg"));
  expect_refused(run_plot, {"--plots", "nodir"});
  EXPECT_EQ(slurp(out), "the previous results");
  EXPECT_TRUE(run_plot.out.empty()) << "no table before the error: " << run_plot.out;
}

TEST_F(BadInput, OutputThatIsADirectoryOrNamedTwiceIsRefusedBeforeAnyWork) {
  std::filesystem::create_directories(path("folder"));
  expect_refused(run("simulate --output " + path("folder")), {"--output", "is a directory"});
  const std::string out = write("same.h5", "keep");
  expect_refused(run("run --output " + out + " --plots " + out), {"named twice"});
  EXPECT_EQ(slurp(out), "keep");
}

}  // namespace
}  // namespace trackassoc
