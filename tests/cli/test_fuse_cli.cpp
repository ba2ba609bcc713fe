// `trackassoc fuse` and the fused RMSE of `trackassoc evaluate`, end to end on a simulated
// recording: every rule writes /fused/<name>, evaluate reports the fused position RMSE beside
// each sensor's (fused below every sensor for naive and bsc), a replaced association drops its
// stale fused tracks, and bad requests exit 2 with one line and nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

class FuseCli : public testing_support::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    sim_ = path("sim.h5");
    file_ = path("a.h5");
    ASSERT_EQ(run("simulate --scenario recorded_3s --output " + sim_).status, 0);
    const testing_support::CliResult r = run("associate --input " + sim_ + " --output " + file_);
    ASSERT_EQ(r.status, 0) << r.err;
  }
  std::string sim_, file_;
};

TEST_F(FuseCli, EveryRuleThenEvaluateReportsFusedBelowEachSensor) {
  const std::string assoc = read_track_file(file_).associations.at(0).name;
  for (const std::string args :
       {"--rule naive", "--rule bsc --name bsc", "--rule ci --ci-criterion det --name ci"}) {
    const testing_support::CliResult r = run("fuse --input " + file_ + " " + args);
    ASSERT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find("fused rows"), std::string::npos) << r.out;
  }
  const testing_support::CliResult bsc = run("fuse --input " + file_ + " --rule bsc --name bsc");
  EXPECT_NE(bsc.out.find("sigma_a = 3 m/s² (the scenario's tracker.process_noise)"), std::string::npos)
      << bsc.out;
  const testing_support::CliResult e = run("evaluate --input " + file_);
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_NE(e.out.find("fused RMSE [m]"), std::string::npos) << e.out;
  const TrackFile f = read_track_file(file_);
  ASSERT_EQ(f.fused.size(), 3u);
  EXPECT_EQ(f.fused[0].name, assoc);
  for (const FusedTrackRecord& r : f.fused) {
    EXPECT_EQ(r.association, assoc);
    ASSERT_GT(r.position_rmse_rows, 500) << r.name;
    ASSERT_EQ(r.sensor_position_rmse.size(), 3u);
    for (std::size_t s = 0; s < 3; ++s) {
      ASSERT_GT(r.sensor_position_rmse_rows[s], 100) << r.name;
      if (r.rule != "ci") {
        EXPECT_LT(r.position_rmse, r.sensor_position_rmse[s]) << r.name << " sensor " << s;
      }
    }
  }
  // Associating again under the same name replaces the association: its fused tracks are stale.
  const testing_support::CliResult again = run("associate --input " + file_ + " --output " + path("b.h5"));
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_TRUE(read_track_file(path("b.h5")).fused.empty());
}

TEST_F(FuseCli, BadRequestsExitTwoAndWriteNothing) {
  const std::string out = path("out.h5");
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"--input " + sim_ + " -o " + out, "/associations is empty; run `trackassoc associate` first"},
      {"--input " + file_ + " --association nope -o " + out, "--association: no /associations/nope"},
      {"--input " + file_ + " --rule naive --correlation 0.3 -o " + out, "apply to --rule bsc only"},
      {"--input " + file_ + " --rule bsc --correlation 0.3 --common-process-noise 1 -o " + out, "not both"},
      {"--input " + file_ + " --rule mean -o " + out, "--rule"},
      {"--input " + file_ + " --rule bsc --correlation 1 -o " + out, "--correlation"},
  };
  for (const Case& c : cases) {
    const testing_support::CliResult r = run("fuse " + c.args);
    EXPECT_EQ(r.status, 2) << c.args;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

}  // namespace
}  // namespace trackassoc
