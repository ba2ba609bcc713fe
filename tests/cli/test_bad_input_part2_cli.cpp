// Bad input, part 2 (issue 15; README, Reliability), as a user's files and commands. Each case must
// end with exit status 2 and one error line on stderr, quickly, and leave an existing output alone.
// A. Crashes, memory and hangs:
//   1. crashes: a scenario JSON nested 100 000 levels deep; a full disk while writing (simulated
//      by RLIMIT_FSIZE in the child: write() fails with EFBIG, as on a full disk, without root);
//   2. memory: sizes inside the documented limits that need gigabytes are refused before they are
//      allocated, by the default budget (half of the physical memory) or a small --memory-budget;
//   3. hangs: the forked reader child dies with its parent.
// B. What a user who mistypes gets:
//   4. out-of-range numbers and misspelt keys were accepted silently with exit 0; they are usage
//      errors now (one line naming the option or key);
//   5. messages that named the wrong cause;
//   6. a second, bad output path replaced the first output before failing; every output path is
//      checked before any work.
// Part 3 (issue 30): tests/cli/test_bad_input_part3_cli.cpp.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/isolated_run.hpp"
#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

namespace fs = std::filesystem;

class BadInputCli : public testing_support::CliFixture {
 protected:
  // Runs the CLI in a child whose files may not grow beyond `max_bytes` (RLIMIT_FSIZE), with
  // SIGXFSZ ignored so that the write fails with EFBIG instead of killing the process. The exit
  // status is -1 when the CLI was killed by a signal (a crash), its signal in `signal`.
  testing_support::CliResult run_with_file_limit(const std::string& args, rlim_t max_bytes, int& signal) {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string command = testing_support::cli_command(args, out, err);
    const pid_t child = ::fork();
    if (child == 0) {
      const rlimit limit{max_bytes, max_bytes};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      ::signal(SIGXFSZ, SIG_IGN);  // inherited through exec: write() returns EFBIG
      ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    int raw = 0;
    ::waitpid(child, &raw, 0);
    signal = WIFSIGNALED(raw) ? WTERMSIG(raw) : 0;
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
  }
  // One error line on stderr, exit status 2, containing every one of `parts`.
  static void expect_refusal(const testing_support::CliResult& r, std::initializer_list<const char*> parts) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err.rfind("trackassoc: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const char* p : parts)
      EXPECT_NE(r.err.find(p), std::string::npos) << "expected '" << p << "' in " << r.err;
  }
  std::string scenario_with(const std::string& replace, const std::string& by) {
    std::ifstream in(std::string(TRACKASSOC_SOURCE_DIR) + "/data/scenarios/seed000.json");
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const auto at = text.find(replace);
    EXPECT_NE(at, std::string::npos) << replace;
    if (at != std::string::npos) text.replace(at, replace.size(), by);
    return write("scenario.json", text);
  }
};

// ---------------------------------------------------------------- 1. crashes

TEST_F(BadInputCli, DeeplyNestedJsonIsRefusedWithoutRecursion) {
  // 100 000 levels: formatting an error about such a value overflowed the stack.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  write("deep.json", "{\"name\": " + deep + "}");
  expect_refusal(run("simulate --scenario " + path("deep.json") + " --output " + path("o.h5")),
                 {"deep.json: JSON nested deeper than 64 levels"});
  EXPECT_FALSE(fs::exists(path("o.h5")));
  // 64 levels are accepted by the parser (the scenario reader then names the wrong type).
  write("ok.json", "{\"name\": " + std::string(63, '[') + std::string(63, ']') + "}");
  const auto r = run("simulate --scenario " + path("ok.json") + " --output " + path("o.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.find("nested deeper"), std::string::npos) << r.err;
  // --options is JSON from the user too.
  expect_refusal(run("solve3d --instance " + std::string(TRACKASSOC_SOURCE_DIR) +
                     "/data/3dap/ap3.5.1.txt --solver greedy --options '{\"a\": " + std::string(1000, '[') +
                     std::string(1000, ']') + "}'"),
                 {"--options: JSON nested deeper than 64 levels"});
}

TEST_F(BadInputCli, FullDiskWhileWritingKeepsTheOldOutputAndExitsCleanly) {
  const std::string sim = path("sim.h5"), assoc = path("assoc.h5"), scored = path("scored.h5");
  ASSERT_EQ(run("simulate --output " + sim).status, 0);
  ASSERT_EQ(run("associate --input " + sim + " --output " + assoc).status, 0);
  ASSERT_EQ(run("evaluate --input " + assoc + " --output " + scored).status, 0);
  const auto size = [](const std::string& p) { return fs::file_size(p); };
  const auto sim_bytes = size(sim), assoc_bytes = size(assoc), scored_bytes = size(scored);
  ASSERT_GT(sim_bytes, 48u * 1024);  // so that a 32 KiB limit stops the writer halfway
  const std::string commands[] = {
      "simulate --seed 2 --output " + sim,                 // replaces sim.h5
      "associate --input " + sim + " --output " + assoc,   // replaces assoc.h5
      "evaluate --input " + assoc + " --output " + scored  // replaces scored.h5
  };
  for (const std::string& c : commands) {
    int signal = 0;
    const auto r = run_with_file_limit(c, 32 * 1024, signal);
    EXPECT_EQ(signal, 0) << c << ": killed by signal " << signal << "; stderr: " << r.err;
    expect_refusal(r, {"(disk full?)", ".h5 is unchanged"});
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << "names the user's file: " << r.err;
    EXPECT_EQ(size(sim), sim_bytes) << c;
    EXPECT_EQ(size(assoc), assoc_bytes) << c;
    EXPECT_EQ(size(scored), scored_bytes) << c;
    EXPECT_FALSE(fs::exists(sim + ".tmp") || fs::exists(assoc + ".tmp") || fs::exists(scored + ".tmp")) << c;
  }
  // The old outputs are whole: they still read.
  EXPECT_EQ(run("evaluate --input " + assoc + " --output " + path("check.h5")).status, 0);
}

// ---------------------------------------------------------------- 2. memory

TEST_F(BadInputCli, ScenarioSizesBeyondTheMemoryBudgetAreRefusedBeforeAllocating) {
  // Inside the scenario reader's limits (count <= 1e7, duration / step <= 1e7), far beyond memory:
  // the default budget refuses them at once.
  std::string json = scenario_with("\"count\": 10", "\"count\": 10000000");
  expect_refusal(run("simulate --scenario " + json + " --output " + path("o.h5")),
                 {"scenario 'seed000' (1e+07 targets", "more than the memory budget of", "--memory-budget"});
  json = scenario_with("\"duration\": 60.0", "\"duration\": 10000000.0");
  expect_refusal(run("simulate --scenario " + json + " --output " + path("o.h5")),
                 {"1e+07 s", "more than the memory budget of", "(half of the physical memory)"});
  EXPECT_FALSE(fs::exists(path("o.h5")));
  // A small budget refuses the default scenario, naming the size and the budget; --memory-budget
  // may come before or after the subcommand.
  expect_refusal(
      run("simulate --memory-budget 0.01 --output " + path("o.h5")),
      {"scenario 'seed000'", "more than the memory budget of 10.2 KiB; raise it with --memory-budget"});
  expect_refusal(run("--memory-budget 0.01 run --output " + path("o.h5")), {"memory budget of 10.2 KiB"});
  EXPECT_EQ(run("simulate --memory-budget 64 --output " + path("o.h5")).status, 0);
  expect_refusal(run("simulate --memory-budget 0 --output " + path("p.h5")),
                 {"--memory-budget: expected a size > 0"});
}

TEST_F(BadInputCli, GeneratorAndPipelineSizesBeyondTheMemoryBudgetAreRefused) {
  expect_refusal(run("dataset seed003 --targets 10000000 --output " + path("d.h5")),
                 {"the seed 003 scene (10000000 targets", "more than the memory budget of"});
  EXPECT_FALSE(fs::exists(path("d.h5")));
  const std::string sim = path("sim.h5");
  ASSERT_EQ(run("simulate --output " + sim).status, 0);
  expect_refusal(
      run("associate --input " + sim + " --output " + path("a.h5") + " --common-period 1e-9"),
      {"the common time grid (", "period 1e-09 s", "see --common-period", "more than the memory budget"});
  EXPECT_FALSE(fs::exists(path("a.h5")));
}

// Replaces every column of /tracks by a chunked dataset of `rows` rows that is never written
// (`only` non-empty: that column only), as a damaged or hostile file would declare them.
void declare_unwritten_rows(const std::string& file, hsize_t rows, const std::string& only = "") {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  struct Column {
    const char* name;
    hid_t type;
    hsize_t width;
  };
  for (const Column& c : {Column{"sensor", H5T_STD_I32LE, 0}, Column{"track", H5T_STD_I32LE, 0},
                          Column{"t", H5T_IEEE_F64LE, 0}, Column{"state", H5T_IEEE_F64LE, 4},
                          Column{"cov", H5T_IEEE_F64LE, 10}, Column{"truth", H5T_STD_I32LE, 0}}) {
    if (!only.empty() && only != c.name) continue;
    const std::string name = std::string("/tracks/") + c.name;
    H5Ldelete(f, name.c_str(), H5P_DEFAULT);
    const int rank = c.width ? 2 : 1;
    const hsize_t dims[2] = {rows, c.width}, chunk[2] = {4096, c.width ? c.width : 1};
    const hid_t space = H5Screate_simple(rank, dims, nullptr), dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, rank, chunk);
    const hid_t set = H5Dcreate2(f, name.c_str(), c.type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(set, 0) << name;
    H5Dclose(set);
    H5Pclose(dcpl);
    H5Sclose(space);
  }
  ASSERT_GE(H5Fclose(f), 0);
}

TEST_F(BadInputCli, TrackFilesDeclaringMoreRowsThanTheyHoldAreRefusedBeforeAllocating) {
  const std::string sim = path("sim.h5");
  ASSERT_EQ(run("simulate --output " + sim).status, 0);
  const std::string hollow = path("hollow.h5"), tall = path("tall.h5");
  fs::copy_file(sim, hollow);
  fs::copy_file(sim, tall);
  // 26 M rows of every column, none written: the file stays small.
  declare_unwritten_rows(hollow, 26214400);
  EXPECT_LT(fs::file_size(hollow), 2 * fs::file_size(sim));
  expect_refusal(run("associate --input " + hollow + " --output " + path("a.h5")),
                 {"hollow.h5: /tracks/sensor: shape 26214400 declares 100 MiB but the file stores 0 bytes"});
  // One column of 2^28 rows: the other columns' lengths are compared before anything is read, and
  // the 64 MiB budget is never approached.
  declare_unwritten_rows(tall, hsize_t{1} << 28, "sensor");
  expect_refusal(run("--memory-budget 64 evaluate --input " + tall + " --output " + path("e.h5")),
                 {"tall.h5: /tracks/track: expected 268435456 rows (as /tracks/sensor), found "});
  // A file whose tables are whole but do not fit the budget beside what the process holds (its
  // code and libraries alone are MiBs): the first table read, the budget and the process, named.
  expect_refusal(run("associate --memory-budget 0.1 --input " + sim + " --output " + path("a.h5")),
                 {"sim.h5: /", "rows of", "needs", "beside the", "more than the memory budget of 102 KiB"});
}

TEST_F(BadInputCli, InstanceHeaderLargerThanItsCostsIsRefusedBeforeAllocating) {
  // 645^3 = 268 336 125 costs declared (1 GB of floats), five given.
  write("big.txt", "3\n645 645 645\n1 2 3 4 5\n");
  expect_refusal(run("solve3d --instance " + path("big.txt") + " --solver greedy"),
                 {"big.txt: line 3: too few costs: expected 268336125 (645x645x645), found 5"});
  // Enough numbers for a small budget to matter: 20^3 floats are 31.2 KiB.
  std::string text = "3\n20 20 20\n";
  for (int i = 0; i < 8000; ++i) text += std::to_string(i % 7) + "\n";
  write("full.txt", text);
  expect_refusal(run("solve3d --memory-budget 0.01 --instance " + path("full.txt") + " --solver greedy"),
                 {"full.txt: tensor 20x20x20 needs 31.2 KiB, more than the memory budget of 10.2 KiB"});
  EXPECT_EQ(run("solve3d --instance " + path("full.txt") + " --solver greedy").status, 0);
}

// ---------------------------------------------------------------- 3. hangs

// The pid of a child of `parent`, or 0 (from /proc/*/stat).
pid_t child_of(pid_t parent) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    std::getline(stat, line);
    const auto close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 2));
    char state = 0;
    pid_t ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent) return static_cast<pid_t>(std::stoi(name));
  }
  return 0;
}

// True while `pid` exists and is not a zombie.
bool alive(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const auto close = line.rfind(')');
  return close != std::string::npos && line.size() > close + 2 && line[close + 2] != 'Z' &&
         line[close + 2] != 'X';
}

TEST_F(BadInputCli, ReaderChildDiesWithItsParent) {
  // libhdf5 loops on this fuzzed file; the CLI reads it in a forked child with a time limit.
  const std::string hang =
      std::string(TRACKASSOC_SOURCE_DIR) + "/tests/fuzz/regressions/hdf5_hang_global_heap.h5";
  const pid_t cli = ::fork();
  if (cli == 0) {
    const std::string out = path("a.h5");
    ::execl(TRACKASSOC_CLI, TRACKASSOC_CLI, "associate", "--input", hang.c_str(), "--output", out.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  pid_t reader = 0;
  for (int i = 0; i < 100 && reader == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    reader = child_of(cli);
  }
  ASSERT_NE(reader, 0) << "the CLI started no reader child";
  ::kill(cli, SIGKILL);  // no timeout, no destructor runs in the parent
  int status = 0;
  ::waitpid(cli, &status, 0);
  bool gone = false;
  for (int i = 0; i < 60 && !gone; ++i) {
    gone = !alive(reader);
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(gone) << "reader child " << reader << " still runs after its parent was killed";
  if (!gone) ::kill(reader, SIGKILL);
}

TEST(IsolatedReadTimeout, GrowsWithTheFileFromTenSeconds) {
  // The damaged 33 KB file is given up after ~10 s (was 60 s); 1 s more per 5 MB.
  const std::string hang =
      std::string(TRACKASSOC_SOURCE_DIR) + "/tests/fuzz/regressions/hdf5_hang_global_heap.h5";
  const double bytes = static_cast<double>(fs::file_size(hang));
  EXPECT_DOUBLE_EQ(isolated_read_timeout(hang), 10.0 + bytes / 5e6);
  EXPECT_DOUBLE_EQ(isolated_read_timeout("/nonexistent/file.h5"), 10.0);
}

// ================================================================ B. mistypes

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

// ---------------------------------------------------------------- 4. silently accepted

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

// ---------------------------------------------------------------- 5. wrong exit or wrong words

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

// ---------------------------------------------------------------- 6. lost output

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
