// `trackassoc associate --solver siamese` end to end: the seed 003 two-radar scene from `simulate`,
// the shipped model by default, a result that beats chance by far (checked against the truth
// independently of `evaluate`), and clear exit-2 errors for missing, corrupt or wrong model files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace fs = std::filesystem;
using trackassoc::testing_support::CliFixture;
using trackassoc::testing_support::CliResult;

namespace {

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Share of the targets seen by both sensors whose two local tracks form one tuple, from the truth.
double correct_pair_rate(const trackassoc::TrackFile& f, const trackassoc::AssociationRecord& a) {
  std::map<std::pair<int32_t, int32_t>, int32_t> target;  // (sensor column, track) → truth
  std::map<int32_t, std::set<int32_t>> columns_of_target;
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t col = f.tracks.sensor[r] == f.sensors[0].id ? 0 : 1;
    target[{col, f.tracks.track[r]}] = f.tracks.truth[r];
    columns_of_target[f.tracks.truth[r]].insert(col);
  }
  int both = 0;
  for (const auto& [t, cols] : columns_of_target) both += cols.size() == 2;
  int correct = 0;
  for (std::size_t k = 0; k < a.num_tuples(); ++k) {
    const int32_t t0 = a.tuples[2 * k], t1 = a.tuples[2 * k + 1];
    if (t0 >= 0 && t1 >= 0 && target.at({0, t0}) == target.at({1, t1})) ++correct;
  }
  return both ? double(correct) / both : 0.0;
}

class SiameseCli : public CliFixture {};

}  // namespace

TEST_F(SiameseCli, AssociatesTheSeed003SceneWithTheShippedModel) {
  ASSERT_EQ(run("simulate --scenario seed003 --output " + path("sim.h5")).status, 0);
  for (const char* points : {"track", "plot"}) {
    const std::string out = path(std::string("assoc_") + points + ".h5");
    const CliResult a = run("associate --input " + path("sim.h5") + " --output " + out +
                            " --solver siamese --threads 2 --options '{\"points\": \"" + points + "\"}'");
    ASSERT_EQ(a.status, 0) << a.err;
    EXPECT_NE(a.out.find("with 'siamese'"), std::string::npos) << a.out;
    const trackassoc::TrackFile f = trackassoc::read_track_file(out);
    ASSERT_EQ(f.sensors.size(), 2u);
    ASSERT_EQ(f.associations.size(), 1u);
    const auto& rec = f.associations[0];
    EXPECT_EQ(rec.name, "siamese");
    EXPECT_EQ(rec.solver, "siamese");
    ASSERT_EQ(rec.num_sensors, 2);
    // Every local track of both sensors in exactly one tuple.
    std::set<std::pair<int, int32_t>> seen, all;
    for (std::size_t r = 0; r < f.tracks.size(); ++r)
      all.insert({f.tracks.sensor[r] == f.sensors[0].id ? 0 : 1, f.tracks.track[r]});
    for (std::size_t k = 0; k < rec.num_tuples(); ++k)
      for (int s = 0; s < 2; ++s)
        if (rec.tuples[2 * k + s] >= 0) {
          EXPECT_TRUE(seen.insert({s, rec.tuples[2 * k + s]}).second);
        }
    EXPECT_EQ(seen, all);
    // 10 targets: a random one-to-one guess gets about 1 in 10 right.
    const double rate = correct_pair_rate(f, rec);
    std::printf("points=%s: correct pair rate %.3f\n", points, rate);
    EXPECT_GE(rate, 0.8) << points;
    // `evaluate` agrees (it counts the same thing for two sensors).
    const CliResult e = run("evaluate --input " + out + " --output " + out + ".scored.h5");
    ASSERT_EQ(e.status, 0) << e.err;
    const trackassoc::TrackFile g = trackassoc::read_track_file(out + ".scored.h5");
    ASSERT_EQ(g.metrics.size(), 1u);
    EXPECT_DOUBLE_EQ(g.metrics[0].correct_rate, rate);
  }
}

TEST_F(SiameseCli, MissingCorruptOrForeignModelIsAOneLineErrorWithExitTwoAndNoOutput) {
  ASSERT_EQ(run("simulate --scenario seed003 --output " + path("sim.h5")).status, 0);
  {
    std::ofstream f(path("garbage.h5"), std::ios::binary);
    for (int i = 0; i < 4096; ++i) f.put(static_cast<char>((i * 2654435761u) >> 13));
  }
  const std::pair<std::string, std::string> cases[] = {
      {path("missing.h5"), "missing.h5"},
      {path("garbage.h5"), "garbage.h5"},
      {path("sim.h5"), "trackassoc-siamese-model"},  // an HDF5 file, but a track file
  };
  for (const auto& [model, expected] : cases) {
    const CliResult r = run("associate --input " + path("sim.h5") + " --output " + path("out.h5") +
                            " --solver siamese --model " + model);
    EXPECT_EQ(r.status, 2) << model;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.h5")));
    EXPECT_FALSE(fs::exists(path("out.h5.tmp")));
  }
  // Bad solver options are refused the same way, naming the key.
  for (const std::string& options :
       {std::string(R"({"sensors": [0, 1, 2]})"), std::string(R"({"thresh": 0.5})"),
        std::string(R"({"threshold": 1.5})"), std::string(R"({"sensors": [0, 9]})")}) {
    const CliResult r = run("associate --input " + path("sim.h5") + " --output " + path("out.h5") +
                            " --solver siamese --options '" + options + "'");
    EXPECT_EQ(r.status, 2) << options;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(path("out.h5")));
  }
}
