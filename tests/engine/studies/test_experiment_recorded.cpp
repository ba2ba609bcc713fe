// experiment recorded (engine/studies/recorded/experiment_recorded.hpp) through the CLI: the table, the HDF5
// rows against the truth of the simulated files, Stone Soup beside them when it imports, and bad input.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/hdf5_wrapper.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;

class ExperimentRecordedCli : public CliFixture {};

TEST_F(ExperimentRecordedCli, WritesOneRowPerMethodScoredAgainstTheTruthAndThePeerBeside) {
  const auto r = run("experiment recorded --scenarios recorded_sync recorded_4s --runs 1 --files " +
                     path("files") + " --output " + path("rec.h5") + " --plots " + path("rec.svg"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("recorded_4s"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(path("files/recorded_sync_run0.h5")));
  EXPECT_TRUE(std::filesystem::exists(path("rec.svg")));
  EXPECT_FALSE(std::filesystem::exists(path("rec.h5.tmp")));
  const h5::File f = h5::File::open_read_only(path("rec.h5"));
  const h5::Group g = f.root().open_group("recorded");
  std::vector<hsize_t> dims;
  const auto method = g.read_integers("method", 1, dims);
  const auto scenario = g.read_integers("scenario", 1, dims);
  const auto targets = g.read_integers("targets", 1, dims);
  const auto correct = g.read_integers("correct", 1, dims);
  const auto false_tuples = g.read_integers("false_tuples", 1, dims);
  // methods: default, unregistered, exact, chi2-sum, 3d-exact, 3d-nogate, stonesoup-one2one,
  // stonesoup-counting, stonesoup-one2one-resampled, stonesoup-counting-resampled; the 3d-* rows
  // only for the three-sensor scenario.
  const bool peer = r.err.find("Stone Soup is not available") == std::string::npos;
  std::size_t expected = 6 + 4 + (peer ? 8 : 0);
  EXPECT_EQ(method.size(), expected) << r.err;
  EXPECT_EQ(g.read_string_attribute("methods"),
            R"(["default","unregistered","exact","chi2-sum","3d-exact","3d-nogate","stonesoup-one2one",)"
            R"("stonesoup-counting","stonesoup-one2one-resampled","stonesoup-counting-resampled"])");
  for (std::size_t q = 0; q < method.size(); ++q) {
    EXPECT_GT(targets[q], 20);
    if (method[q] <= 1) {  // the default, with and without registration: every target of both files
      EXPECT_EQ(correct[q], targets[q]) << "scenario " << scenario[q];
      EXPECT_EQ(false_tuples[q], 0);
    }
    if (method[q] == 6 && scenario[q] == 0) {
      EXPECT_EQ(correct[q], targets[q]);  // Stone Soup, synchronous
    }
    if ((method[q] == 6 || method[q] == 7) && scenario[q] == 1) {
      EXPECT_EQ(correct[q], 0);  // as shipped: no shared timestamps on asynchronous radars
    }
    if (method[q] == 8 && scenario[q] == 1) {  // predicted onto a common grid: the same associator links
      EXPECT_GE(correct[q], 0.9 * targets[q]);
    }
  }
}

TEST_F(ExperimentRecordedCli, BadInputIsExitTwoAndWritesNothing) {
  auto r = run("experiment recorded --scenarios recorded_sync --methods bogus --no-peer --files " +
               path("f") + " --output " + path("x.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bogus"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("x.h5")));
  r = run("experiment recorded --scenarios no_such_scenario --no-peer --files " + path("f") + " --output " +
          path("y.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_FALSE(std::filesystem::exists(path("y.h5")));
}

TEST_F(ExperimentRecordedCli, AScenarioFileInAnotherFolderNamesItsFilesByItsFileName) {
  // Was: --files/<the whole path>_run0.h5, "output folder ... does not exist".
  std::filesystem::create_directories(path("scenarios"));
  std::filesystem::copy_file(std::string(TRACKASSOC_SOURCE_DIR) + "/data/scenarios/recorded_sync.json",
                             path("scenarios/mine.json"));
  const auto r = run("experiment recorded --scenarios " + path("scenarios/mine.json") +
                     " --methods default --runs 1 --no-peer --no-plots --files " + path("files") +
                     " --output " + path("rec.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(path("files/mine.json_run0.h5")));
}

}  // namespace
}  // namespace trackassoc
