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
    ASSERT_EQ(run("export csv --input " + path("sim.h5") + " --output " + path("t.csv") + " --mapping-output " +
                  path("m.json"))
                  .status,
              0);
  }
};

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
      EXPECT_TRUE(has(one.out, "  " + key + " ")) << key << " not listed by `solvers " << name << "`:\n" << one.out;
      ++listed;
      start = end + 2;
    }
    EXPECT_GE(listed, 3u) << keys;
  }
  // With no names, every solver: the three among them.
  const CliResult all = run("solvers");
  ASSERT_EQ(all.status, 0);
  for (const char* name : {"\nfuzzy: ", "\nftaa: ", "\nsiamese: ", "\nlr+ls: "}) EXPECT_TRUE(has(all.out, name)) << name;
  expect_refusal(run("solvers fuzy"), {"unknown solver 'fuzy' (did you mean 'fuzzy'?)"});
}

}  // namespace
}  // namespace trackassoc
