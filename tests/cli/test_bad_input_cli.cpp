// Bad input, part 2 (README, Reliability): inputs that used to crash the CLI, exhaust the memory or
// hang it, written as a user's files and commands. Each must end with one error line on stderr and
// exit status 2, quickly, and leave an existing output file as it was.
//   1. crashes: a scenario JSON nested 100 000 levels deep; a full disk while writing (simulated
//      by RLIMIT_FSIZE in the child: write() fails with EFBIG, as on a full disk, without root);
//   2. memory: sizes inside the documented limits that need gigabytes are refused before they are
//      allocated, by the default budget (half of the physical memory) or a small --memory-budget;
//   3. hangs: the forked reader child dies with its parent.
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
#include "tests/support/cli_runner.hpp"

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
  const std::string sim = path("sim.h5"), assoc = path("assoc.h5");
  ASSERT_EQ(run("simulate --output " + sim).status, 0);
  ASSERT_EQ(run("associate --input " + sim + " --output " + assoc).status, 0);
  const auto size = [](const std::string& p) { return fs::file_size(p); };
  const auto sim_bytes = size(sim), assoc_bytes = size(assoc);
  ASSERT_GT(sim_bytes, 48u * 1024);  // so that a 32 KiB limit stops the writer halfway
  const std::string commands[] = {
      "simulate --seed 2 --output " + sim,                // replaces sim.h5
      "associate --input " + sim + " --output " + assoc,  // replaces assoc.h5
      "evaluate --input " + assoc,                        // in place
  };
  for (const std::string& c : commands) {
    int signal = 0;
    const auto r = run_with_file_limit(c, 32 * 1024, signal);
    EXPECT_EQ(signal, 0) << c << ": killed by signal " << signal << "; stderr: " << r.err;
    expect_refusal(r, {"(disk full?)", ".h5 is unchanged"});
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << "names the user's file: " << r.err;
    EXPECT_EQ(size(sim), sim_bytes) << c;
    EXPECT_EQ(size(assoc), assoc_bytes) << c;
    EXPECT_FALSE(fs::exists(sim + ".tmp") || fs::exists(assoc + ".tmp")) << c;
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
  // A file whose tables are whole but larger than the budget: the budget, named.
  expect_refusal(run("associate --memory-budget 0.1 --input " + sim + " --output " + path("a.h5")),
                 {"sim.h5: /tracks (", "rows of 6 columns) needs", "more than the memory budget of 102 KiB"});
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

}  // namespace
}  // namespace trackassoc
