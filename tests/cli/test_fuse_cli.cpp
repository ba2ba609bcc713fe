// `trackassoc fuse` and the fused RMSE of `trackassoc evaluate`, end to end on a simulated
// recording: every rule writes /fused/<name>, evaluate reports the fused position RMSE beside
// each sensor's (fused below every sensor for naive and bsc), a replaced association drops its
// stale fused tracks, the reports corrected by the association's /registration (and as recorded
// with --no-registration), and bad requests exit 2 with one line and nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/hdf5_wrapper.hpp"
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
  // Each fusion into a new file (fuse never writes over its input), the next reading the last.
  std::string last = file_;
  int k = 0;
  for (const std::string args : {"--rule naive", "--rule bsc --name bsc",
                                 "--rule ci --ci-criterion det --name ci", "--rule bsc --name bsc"}) {
    const std::string next = path("f" + std::to_string(++k).append(".h5"));
    const testing_support::CliResult r = run("fuse --input " + last + " " + args + " -o " + next);
    ASSERT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find("fused rows"), std::string::npos) << r.out;
    if (k == 4) {
      EXPECT_NE(r.out.find("sigma_a = 3 m/s² (the scenario's tracker.process_noise)"), std::string::npos)
          << r.out;
    }
    last = next;
  }
  // The input itself is refused as the output, and --output is required.
  const std::string before = slurp(last);
  const testing_support::CliResult same = run("fuse --input " + last + " --rule naive -o " + last);
  EXPECT_EQ(same.status, 2);
  EXPECT_NE(same.err.find("--output"), std::string::npos) << same.err;
  EXPECT_EQ(slurp(last), before);
  EXPECT_NE(run("fuse --input " + last + " --rule naive").status, 0);
  EXPECT_EQ(slurp(last), before);
  const testing_support::CliResult e = run("evaluate --input " + last + " --output " + file_ + ".scored.h5");
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_NE(e.out.find("fused RMSE [m]"), std::string::npos) << e.out;
  const TrackFile f = read_track_file(file_ + ".scored.h5");
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

TEST_F(FuseCli, RegisteredReportsByDefaultAsRecordedWithNoRegistration) {
  const std::string sim = path("bias_sim.h5"), file = path("bias.h5");
  ASSERT_EQ(run("simulate --scenario recorded_bias --output " + sim).status, 0);
  ASSERT_EQ(run("associate --input " + sim + " --output " + file).status, 0);
  const TrackFile associated = read_track_file(file);
  ASSERT_TRUE(associated.registration && associated.registration->applied);
  // /registration/covariance: S × k × k, its diagonal the squared standard errors.
  {
    const RegistrationRecord& r = *associated.registration;
    const std::size_t S = r.sensor.size(), k = r.parameters.size();
    std::vector<hsize_t> dims;
    const std::vector<double> cov =
        h5::File::open_read_only(file).root().open_group("registration").read_doubles("covariance", 3, dims);
    ASSERT_EQ(dims, (std::vector<hsize_t>{S, k, k}));
    for (std::size_t s = 0; s < S; ++s)
      for (std::size_t j = 0; j < k; ++j)
        EXPECT_NEAR(std::sqrt(cov[(s * k + j) * k + j]), r.standard_error[s * k + j],
                    1e-12 * (1 + r.standard_error[s * k + j]));
  }
  const testing_support::CliResult on = run("fuse --input " + file + " -o " + path("on.h5"));
  ASSERT_EQ(on.status, 0) << on.err;
  EXPECT_NE(on.out.find("registration: reports corrected by /registration"), std::string::npos) << on.out;
  const testing_support::CliResult off =
      run("fuse --input " + path("on.h5") + " --no-registration --name raw -o " + path("both.h5"));
  ASSERT_EQ(off.status, 0) << off.err;
  EXPECT_NE(off.out.find("registration: not applied (switched off)"), std::string::npos) << off.out;
  // Without /registration in the file, the same fusion as --no-registration, to the bit.
  TrackFile plain = associated;
  plain.registration.reset();
  write_track_file(path("plain.h5"), plain);
  const testing_support::CliResult recorded =
      run("fuse --input " + path("plain.h5") + " --name raw -o " + path("plain_fused.h5"));
  ASSERT_EQ(recorded.status, 0) << recorded.err;
  EXPECT_NE(recorded.out.find("registration: no /registration in the file"), std::string::npos)
      << recorded.out;
  const TrackFile f = read_track_file(path("both.h5")), g = read_track_file(path("plain_fused.h5"));
  ASSERT_EQ(f.fused.size(), 2u);
  const FusedTrackRecord &registered = f.fused[0], &raw = f.fused[1];
  EXPECT_TRUE(nlohmann::json::parse(registered.options_json).at("registration").get<bool>());
  EXPECT_FALSE(nlohmann::json::parse(raw.options_json).at("registration").get<bool>());
  EXPECT_EQ(raw.state, g.fused.at(0).state);
  EXPECT_EQ(raw.cov, g.fused.at(0).cov);
  // The correction moves the fused states: the biases are hundreds of metres (recorded_bias).
  ASSERT_EQ(registered.t, raw.t);
  double moved = 0.0;
  for (std::size_t i = 0; i < raw.size(); ++i)
    moved = std::max(moved, std::hypot(registered.state[0][i] - raw.state[0][i],
                                       registered.state[1][i] - raw.state[1][i]));
  EXPECT_GT(moved, 100.0);
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
