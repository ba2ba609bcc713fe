// `trackassoc filter` end to end: every filter turns /measurements into readable /tracks, the IMM
// adds /tracks/model_prob, the alpha-beta tracks are plausible beside the Kalman ones, bad options
// are rejected with one clear line and no output file.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace fs = std::filesystem;

namespace trackassoc {
namespace {

class FilterCli : public testing_support::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    Scenario sc;
    sc.duration = 30;
    sc.random_targets.count = 5;
    sc.random_targets.area_max = {20e3, 20e3, 0};
    sc.random_targets.speed_min = 100, sc.random_targets.speed_max = 200;
    sc.random_targets.process_noise = 2.0;
    for (int s = 0; s < 2; ++s) {
      Sensor x;
      x.id = s;
      x.position = {-30e3 + 60e3 * s, 0, 0};
      x.p_detect = 0.9;
      x.clutter_rate = 1.0;
      sc.sensors.push_back(x);
    }
    input_ = (dir_ / "in.h5").string();
    write_track_file(input_, simulation_to_track_file(sc, simulate(sc, 3, 0)));
  }
  int run(const std::string& args, std::string* err = nullptr) {
    const testing_support::CliResult r = CliFixture::run(args);
    if (err) *err = r.err;
    return r.status;
  }
  std::string input_;
};

TEST_F(FilterCli, EveryFilterWritesReadableTracks) {
  for (const std::string f : {"cv", "ca", "ab", "cs", "cs-nn", "imm"}) {
    const std::string out = path("out_" + f + ".h5");
    std::string err;
    ASSERT_EQ(run("filter --input " + input_ + " --filter " + f + " --output " + out, &err), 0)
        << f << ": " << err;
    const TrackFile file = read_track_file(out);
    EXPECT_GT(file.tracks.size(), 100u) << f;
    EXPECT_TRUE(file.associations.empty());
    for (int32_t t : file.tracks.truth) ASSERT_GE(t, 0);
    h5::File h = h5::File::open_read_only(out);
    const bool has_prob = h.root().open_group("tracks").has("model_prob");
    EXPECT_EQ(has_prob, f == "imm") << f;
    if (has_prob) {
      std::vector<hsize_t> dims;
      const auto mu = h.root().open_group("tracks").read_doubles("model_prob", 2, dims);
      ASSERT_EQ(dims.size(), 2u);
      EXPECT_EQ(dims[0], file.tracks.size());
      EXPECT_EQ(dims[1], 2u);
      for (std::size_t i = 0; i < dims[0]; ++i) EXPECT_NEAR(mu[2 * i] + mu[2 * i + 1], 1.0, 1e-12);
    }
  }
}

// The alpha-beta tracks report the same (sensor, track, t, truth) rows as the CV Kalman filter, and
// their estimates differ from the Kalman ones by less than their own reported position σ: the
// Kalman error is (nearly) orthogonal to the difference, so E|ab − cv|² ≈ E|e_ab|² − E|e_cv|² ≤
// tr P_ab,pos when the α-β covariance is honest.
TEST_F(FilterCli, AlphaBetaTracksArePlausible) {
  const std::string ab = path("ab.h5"), cv = path("cv.h5");
  std::string err;
  ASSERT_EQ(run("filter --input " + input_ + " --filter ab --process-noise 2 --output " + ab, &err), 0)
      << err;
  ASSERT_EQ(run("filter --input " + input_ + " --filter cv --process-noise 2 --output " + cv, &err), 0)
      << err;
  const TrackFile a = read_track_file(ab), c = read_track_file(cv);
  ASSERT_EQ(a.tracks.size(), c.tracks.size());
  EXPECT_EQ(a.tracks.sensor, c.tracks.sensor);
  EXPECT_EQ(a.tracks.track, c.tracks.track);
  EXPECT_EQ(a.tracks.t, c.tracks.t);
  EXPECT_EQ(a.tracks.truth, c.tracks.truth);
  EXPECT_NE(a.tracks.state, c.tracks.state);
  double diff2 = 0.0, trace = 0.0;
  for (std::size_t i = 0; i < a.tracks.size(); ++i) {
    const Eigen::VectorXd d = a.tracks.state_at(i) - c.tracks.state_at(i);
    const Eigen::MatrixXd P = a.tracks.cov_at(i);
    diff2 += d.head(2).squaredNorm();
    trace += P(0, 0) + P(1, 1);
  }
  EXPECT_LT(diff2, trace);
  EXPECT_GT(diff2, 0.0);
}

TEST_F(FilterCli, SameTracksForOneAndTwoThreads) {
  ASSERT_EQ(run("filter --threads 1 --input " + input_ + " --filter imm --output " + path("a.h5")), 0);
  ASSERT_EQ(run("filter --threads 2 --input " + input_ + " --filter imm --output " + path("b.h5")), 0);
  const TrackFile a = read_track_file(path("a.h5")), b = read_track_file(path("b.h5"));
  EXPECT_EQ(a.tracks.state, b.tracks.state);
  EXPECT_EQ(a.tracks.cov, b.tracks.cov);
}

TEST_F(FilterCli, BadOptionsAreRejectedWithoutOutput) {
  std::string err;
  EXPECT_EQ(run("filter --input " + input_ + " --filter kalman --output " + path("x.h5"), &err), 2);
  EXPECT_NE(err.find("--filter"), std::string::npos) << err;
  // The alpha-beta filter's Kalata gains need a process noise σ > 0.
  EXPECT_EQ(run("filter --input " + input_ + " --filter ab --process-noise 0 --output " + path("x.h5"), &err),
            2);
  EXPECT_NE(err.find("--process-noise"), std::string::npos) << err;
  EXPECT_EQ(
      run("filter --input " + input_ + " --filter cv --process-noise -3 --output " + path("x.h5"), &err), 2);
  EXPECT_NE(err.find("--process-noise"), std::string::npos) << err;
  EXPECT_EQ(run("filter --input " + path("missing.h5") + " --filter cv --output " + path("x.h5"), &err), 2);
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

}  // namespace
}  // namespace trackassoc
