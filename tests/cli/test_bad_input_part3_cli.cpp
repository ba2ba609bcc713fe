// Bad input, part 3 (issue 30, README Reliability), as a user's files and commands:
//   1. an output that is one of the command's inputs is refused before any work, compared as the
//      same file (device and inode: a symlink, a hard link or "./" cannot hide it);
//   2. error lines never echo raw control bytes, are never cut at a NUL, and UTF-16 text is named;
//   4. `solvers` lists every solver `associate` accepts;
//   5. `import csv` caps the length of a line;
//   6. names are checked before any work; a missing /tracks/truth is called missing.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

namespace fs = std::filesystem;
using testing_support::CliResult;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class BadInputPart3 : public testing_support::CliFixture {
 protected:
  // One error line on stderr, exit status 2, holding every one of `parts`; nothing on stdout.
  static void expect_refusal(const CliResult& r, std::initializer_list<std::string> parts) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err.rfind("trackassoc: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.out, "");
    for (const auto& p : parts) EXPECT_TRUE(has(r.err, p)) << "expected '" << p << "' in " << r.err;
  }
  // Every byte of an error line is printable ASCII or part of UTF-8 text, but for its final '\n'.
  static void expect_printable(const std::string& err) {
    for (std::size_t i = 0; i + 1 < err.size(); ++i) {
      const auto c = static_cast<unsigned char>(err[i]);
      EXPECT_TRUE(c >= 0x20 && c != 0x7f) << "raw byte " << int(c) << " at " << i << " of " << err;
    }
  }
  std::string write_bytes(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  // A simulated file and its CSV export with the mapping.
  void make_csv() {
    ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
    ASSERT_EQ(run("export csv --input " + path("sim.h5") + " --output " + path("t.csv") +
                  " --mapping-output " + path("m.json"))
                  .status,
              0);
  }
};

// ---------------------------------------------------------------- 1. an output is never an input

TEST_F(BadInputPart3, AnOutputThatIsAnInputIsRefusedBeforeAnyWork) {
  make_csv();
  fs::create_symlink(path("t.csv"), path("alias.csv"));  // the same file under another name
  fs::create_hard_link(path("sim.h5"), path("hard.h5"));
  write("scenario.json", slurp(std::string(TRACKASSOC_SOURCE_DIR) + "/data/scenarios/recorded_3s.json"));
  const std::string csv = path("t.csv"), map = path("m.json"), sim = path("sim.h5");
  const std::string import = "import csv --input " + csv + " --mapping " + map + " --output ";
  struct Case {
    std::string args, output, input;  // the command, the output's option and path, the input's option
  };
  const std::string dot = (dir_ / "." / "t.csv").string();  // "..././t.csv"
  const Case cases[] = {
      {import + csv, "--output " + csv, "--input " + csv},
      {import + map, "--output " + map, "--mapping " + map},
      {import + dot, "--output " + dot, "--input " + csv},
      {import + path("alias.csv"), "--output " + path("alias.csv"), "--input " + csv},
      {"export csv --input " + sim + " --output " + sim, "--output " + sim, "--input " + sim},
      {"export csv --input " + sim + " --output " + path("o.csv") + " --mapping-output " + sim,
       "--mapping-output " + sim, "--input " + sim},
      {"export csv --input " + sim + " --output " + path("hard.h5"), "--output " + path("hard.h5"),
       "--input " + sim},
      {"associate --input " + sim + " --output " + sim, "--output " + sim, "--input " + sim},
      {"filter --input " + sim + " --output " + path("hard.h5"), "--output " + path("hard.h5"),
       "--input " + sim},
      {"simulate --scenario " + path("scenario.json") + " --output " + path("scenario.json"),
       "--output " + path("scenario.json"), "--scenario " + path("scenario.json")},
      {"run --scenario " + path("scenario.json") + " --no-plots --output " + path("scenario.json"),
       "--output " + path("scenario.json"), "--scenario " + path("scenario.json")},
      {"experiment recorded --scenarios " + path("scenario.json") +
           " --runs 1 --no-peer --no-plots --output " + path("scenario.json"),
       "--output " + path("scenario.json"), "--scenarios " + path("scenario.json")},
  };
  const std::string files[] = {csv, map, sim, path("scenario.json")};
  std::vector<std::string> before;
  for (const auto& f : files) before.push_back(slurp(f));
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    expect_refusal(run(c.args), {c.output + ": is the input " + c.input + " (the same file)"});
    for (std::size_t k = 0; k < std::size(files); ++k) EXPECT_EQ(slurp(files[k]), before[k]) << files[k];
    EXPECT_FALSE(fs::exists(path("o.csv")));  // the first output of a refused command is not written
    for (const auto& e : fs::directory_iterator(dir_)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  }
  // A distinct output of the same commands still works, and fuse and evaluate still update their
  // input in place when no --output is given.
  const CliResult ok = run(import + path("r.h5"));
  EXPECT_EQ(ok.status, 0) << ok.err;
}

// ---------------------------------------------------------------- 2. error lines are text

TEST_F(BadInputPart3, ControlBytesInAnInputAreEscapedInTheErrorLine) {
  const std::string cols =
      " -c time=t -c sensor=sensor -c track=track -c x=x -c y=y --sigma-pos 5 --sigma-vel 1 -o ";
  // A header holding the bell and a terminal escape sequence (red text): the column list of the
  // message shows them as \x07 and \x1b.
  write_bytes("esc.csv", "time\x07,\x1b[31mred,sensor,track,x,y\n0,1,0,1,2,3\n");
  CliResult r = run("import csv -i " + path("esc.csv") + cols + path("o.h5"));
  expect_refusal(r, {"column 't' is not in the header (line 1: time\\x07, \\x1b[31mred, sensor"});
  expect_printable(r.err);
  // A value with control bytes and a NUL-free binary run: escaped in the "found '...'" preview.
  write_bytes("val.csv", "t,sensor,track,x,y\n0,1,0,1\x01\x04\x07,2\n");
  r = run("import csv -i " + path("val.csv") + cols + path("o.h5"));
  expect_refusal(r, {"line 2, column 'x': expected a number, found '1\\x01\\x04\\x07'"});
  expect_printable(r.err);
  // A binary file (NUL bytes): named as not text, the line whole, not cut at the NUL.
  write_bytes("bin.csv", "t,sensor,track,x,y\n" + std::string("\x01\0\x04\x07garbage\0\n", 13));
  r = run("import csv -i " + path("bin.csv") + cols + path("o.h5"));
  expect_refusal(r, {"bin.csv: line 2: not UTF-8 text (UTF-16? save as UTF-8 CSV): found NUL bytes"});
  expect_printable(r.err);
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

TEST_F(BadInputPart3, Utf16TextIsNamedAsSuch) {
  // Excel's "Unicode text": UTF-16 little-endian with a byte-order mark.
  auto utf16 = [](const std::string& ascii) {
    std::string s = "\xff\xfe";
    for (char c : ascii) s += std::string{c, '\0'};
    return s;
  };
  write_bytes("u16.csv", utf16("t,sensor,track,x,y\n0,1,0,1,2\n"));
  CliResult r =
      run("import csv -i " + path("u16.csv") +
          " -c time=t -c sensor=sensor -c track=track -c x=x -c y=y --sigma-pos 5 --sigma-vel 1 -o " +
          path("o.h5"));
  expect_refusal(
      r, {"u16.csv: line 1: not UTF-8 text (UTF-16? save as UTF-8 CSV): found a UTF-16 byte-order mark"});
  expect_printable(r.err);
  // The mapping JSON and a scenario JSON saved as UTF-16 alike.
  write("t.csv", "t,sensor,track,x,y\n0,1,0,1,2\n");
  write_bytes("m.json", utf16(R"({"time": "t", "sensor": "sensor", "track": "track", "x": "x", "y": "y"})"));
  r = run("import csv -i " + path("t.csv") + " -m " + path("m.json") + " --sigma-pos 5 --sigma-vel 1 -o " +
          path("o.h5"));
  expect_refusal(r, {"m.json: not UTF-8 text (UTF-16? save as UTF-8): found a UTF-16 byte-order mark"});
  write_bytes("s.json", utf16("{}"));
  r = run("simulate --scenario " + path("s.json") + " --output " + path("o.h5"));
  expect_refusal(r, {"s.json", "not UTF-8 text (UTF-16? save as UTF-8)"});
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

// ---------------------------------------------------------------- 4. every solver is listed

TEST_F(BadInputPart3, SolversListsEverySolverAssociateAccepts) {
  const CliResult r = run("solvers fuzzy ftaa siamese");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"fuzzy", "ftaa", "siamese"})
    EXPECT_TRUE(has(r.out, std::string("\n") + name + ": ") || r.out.rfind(std::string(name) + ": ", 0) == 0)
        << name << " in " << r.out;
  // The keys listed are the keys associate reads: a misspelt key's error lists the known ones.
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  for (const char* name : {"fuzzy", "ftaa", "siamese"}) {
    SCOPED_TRACE(name);
    const CliResult bad = run("associate --input " + path("sim.h5") + " --output " + path("o.h5") +
                              " --solver " + name + " --options '{\"no_such_key\": 1}'");
    ASSERT_EQ(bad.status, 2) << bad.err;
    const auto at = bad.err.find("known keys: ");
    ASSERT_NE(at, std::string::npos) << bad.err;
    std::string keys = bad.err.substr(at + 12);
    keys = keys.substr(0, keys.find_first_of(")\n"));
    const CliResult one = run(std::string("solvers ") + name);
    ASSERT_EQ(one.status, 0) << one.err;
    std::size_t listed = 0;
    for (std::size_t start = 0; start < keys.size();) {
      const std::size_t end = std::min(keys.find(", ", start), keys.size());
      const std::string key = keys.substr(start, end - start);
      EXPECT_TRUE(has(one.out, "  " + key + " ")) << key << " not listed by `solvers " << name << "`:\n"
                                                  << one.out;
      ++listed;
      start = end + 2;
    }
    EXPECT_GE(listed, 3u) << keys;
  }
  // With no names, every solver: the three among them.
  const CliResult all = run("solvers");
  ASSERT_EQ(all.status, 0);
  for (const char* name : {"\nfuzzy: ", "\nftaa: ", "\nsiamese: ", "\nlr+ls: "})
    EXPECT_TRUE(has(all.out, name)) << name;
  expect_refusal(run("solvers fuzy"), {"unknown solver 'fuzy' (did you mean 'fuzzy'?)"});
}

// ---------------------------------------------------------------- 5. the CSV line cap

TEST_F(BadInputPart3, ALineLongerThanTheCapIsRefusedNamingIt) {
  const std::string cols =
      " -c time=t -c sensor=sensor -c track=track -c x=x -c y=y --sigma-pos 5 --sigma-vel 1 -o ";
  // A 3 MiB header line (a file with no line breaks, or the wrong file).
  write("long.csv", "t,sensor,track,x,y," + std::string(3 << 20, 'a') + "\n0,1,0,1,2,3\n");
  CliResult r = run("import csv -i " + path("long.csv") + cols + path("o.h5"));
  expect_refusal(r, {"long.csv: line 1 is longer than 1048576 bytes (the cap of a CSV line)"});
  // A long data line: its number; a line of exactly the cap is read (and then named for its fields).
  write("data.csv", "t,sensor,track,x,y\n0,1,0,1,2\n1,1,0,1," + std::string((1 << 20) + 1, '2') + "\n");
  r = run("import csv -i " + path("data.csv") + cols + path("o.h5"));
  expect_refusal(r, {"data.csv: line 3 is longer than 1048576 bytes"});
  const std::string exact = "1,1,0,1,";
  write("cap.csv",
        "t,sensor,track,x,y\n0,1,0,1,2\n" + exact + std::string((1 << 20) - exact.size(), '2') + "\n");
  r = run("import csv -i " + path("cap.csv") + cols + path("o.h5"));
  expect_refusal(r, {"cap.csv: line 3, column 'y': number out of the double range: '2222"});
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

// ---------------------------------------------------------------- 6. early and right words

TEST_F(BadInputPart3, NamesAreCheckedBeforeAnyWork) {
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  ASSERT_EQ(run("associate --input " + path("sim.h5") + " --output " + path("a.h5")).status, 0);
  const std::string a = slurp(path("a.h5"));
  for (const std::string name : {".", "a/b"}) {
    SCOPED_TRACE(name);
    expect_refusal(run("fuse --input " + path("a.h5") + " --name '" + name + "' -o " + path("f.h5")),
                   {"--name: /fused: invalid name '" + name + "'"});
    EXPECT_EQ(slurp(path("a.h5")), a);
    expect_refusal(
        run("associate --input " + path("sim.h5") + " --output " + path("b.h5") + " --name '" + name + "'"),
        {"--name: /associations: invalid name '" + name + "'"});
    EXPECT_FALSE(fs::exists(path("b.h5")));
  }
  // A name with a real control byte: refused, and shown escaped.
  const CliResult r =
      run("fuse --input " + path("a.h5") + " --name \"$(printf 'x\\033y')\" -o " + path("f.h5"));
  expect_refusal(r, {"invalid name 'x\\x1by'"});
  expect_printable(r.err);
}

TEST_F(BadInputPart3, EvaluateSaysAMissingTruthDatasetIsMissing) {
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  ASSERT_EQ(run("associate --input " + path("sim.h5") + " --output " + path("a.h5")).status, 0);
  // The same file as another program may write it: no /tracks/truth.
  const hid_t f = H5Fopen(path("a.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Ldelete(f, "/tracks/truth", H5P_DEFAULT), 0);
  H5Fclose(f);
  expect_refusal(run("evaluate --input " + path("a.h5") + " --output " + path("e.h5")),
                 {"a.h5: /tracks/truth: missing dataset"});
  EXPECT_FALSE(fs::exists(path("e.h5")));
}

}  // namespace
}  // namespace trackassoc
