// `trackassoc import csv` and `export csv` as a user runs them (tests/support/cli_runner.hpp): the round
// trip simulate → export csv → import csv → associate gives the tuples of associate on the
// original file; bad CSV and bad mapping JSON exit 2 naming line and column (or the key) and
// write nothing; geodetic input and the σ flags from the command line.
#include <filesystem>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;
using testing_support::CliResult;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class CsvCli : public CliFixture {};

TEST_F(CsvCli, RoundTripThroughCsvGivesTheSameAssociation) {
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  CliResult r = run("associate --input " + path("sim.h5") + " --output " + path("a.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  r = run("export csv --input " + path("sim.h5") + " --output " + path("t.csv") + " --mapping-output " +
          path("m.json"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "exported")) << r.out;
  r = run("import csv --input " + path("t.csv") + " --mapping " + path("m.json") + " --output " +
          path("r.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "velocity columns; covariance columns")) << r.out;
  r = run("associate --input " + path("r.h5") + " --output " + path("b.h5"));
  ASSERT_EQ(r.status, 0) << r.err;

  const TrackFile sim = read_track_file(path("sim.h5")), imported = read_track_file(path("r.h5"));
  EXPECT_EQ(imported.tracks.t, sim.tracks.t);
  EXPECT_EQ(imported.tracks.state, sim.tracks.state);
  EXPECT_EQ(imported.tracks.cov, sim.tracks.cov);
  EXPECT_EQ(imported.tracks.truth, sim.tracks.truth);
  ASSERT_EQ(imported.sensors.size(), sim.sensors.size());
  for (std::size_t s = 0; s < sim.sensors.size(); ++s) {
    EXPECT_EQ(imported.sensors[s].id, sim.sensors[s].id);
    EXPECT_EQ(imported.sensors[s].period, sim.sensors[s].period);  // 3, 4, 5 s from the reports
  }
  const TrackFile a = read_track_file(path("a.h5")), b = read_track_file(path("b.h5"));
  ASSERT_EQ(a.associations.size(), 1u);
  ASSERT_EQ(b.associations.size(), 1u);
  EXPECT_GT(a.associations[0].num_tuples(), 10u);
  EXPECT_EQ(b.associations[0].tuples, a.associations[0].tuples);
  EXPECT_EQ(b.associations[0].cost, a.associations[0].cost);
}

TEST_F(CsvCli, BadCsvExitsTwoNamingLineAndColumnAndWritesNothing) {
  write("t.csv", "t,sensor,track,x,y\n0,1,0,1,2\n1,1,0,oops,2\n2,1,0,3\n");
  const CliResult r = run("import csv -i " + path("t.csv") +
                          " -c time=t -c sensor=sensor -c track=track -c x=x -c y=y "
                          "--sigma-pos 5 --sigma-vel 1 -o " +
                          path("out.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "2 bad values: line 3, column 'x': expected a number, found 'oops'")) << r.err;
  EXPECT_TRUE(has(r.err, "line 4: 4 fields, the header has 5")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.h5")));
  EXPECT_FALSE(std::filesystem::exists(path("out.h5.tmp")));
}

TEST_F(CsvCli, BadMappingJsonExitsTwoNamingTheKey) {
  write("t.csv", "t,sensor,track,x,y\n0,1,0,1,2\n");
  write("bad.json",
        R"({"time": "t", "sensor": "sensor", "track": "track", "x": "x", "y": "y", "sigma_x": "s"})");
  CliResult r = run("import csv -i " + path("t.csv") + " -m " + path("bad.json") + " -o " + path("out.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "mapping key 'sigma_x' is unknown")) << r.err;
  write("broken.json", R"({"time": "t", )");
  r = run("import csv -i " + path("t.csv") + " -m " + path("broken.json") + " -o " + path("out.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "invalid JSON")) << r.err;
  write("wrong.json", R"({"time": "time", "sensor": "sensor", "track": "track", "x": "x", "y": "y"})");
  r = run("import csv -i " + path("t.csv") + " -m " + path("wrong.json") + " -o " + path("out.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "mapping key 'time': column 'time' is not in the header")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.h5")));
}

TEST_F(CsvCli, GeodeticSemicolonFileWithSigmaFlags) {
  write("g.csv",
        "time;radar;id;lat;lon\n"
        "0;7;1;63.4;10.4\n1;7;1;63.401;10.4\n"
        "0;9;1;63.4001;10.4\n2;9;1;63.4011;10.4\n");
  write("m.json", R"({"time": "time", "sensor": "radar", "track": "id", "lat": "lat", "lon": "lon"})");
  const CliResult r =
      run("import csv -i " + path("g.csv") + " -m " + path("m.json") +
          " --delimiter ';' --origin 63.4,10.4,0 --sigma-pos 7:5,9:20 --sigma-vel 2 -o " + path("g.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "4 reports of 2 tracks from 2 sensors (x,y,vx,vy, ENU; velocity estimated"))
      << r.out;
  const TrackFile f = read_track_file(path("g.h5"));
  EXPECT_EQ(f.recording.frame, "ENU");
  EXPECT_NEAR(f.tracks.state[1][1], 111.468, 2e-3);  // north of the origin (test_io_csv_import.cpp)
  EXPECT_NEAR(f.tracks.state[3][1], 111.468, 2e-3);  // v_north of sensor 7's two reports 1 s apart
  EXPECT_EQ(f.tracks.cov[packed_index(4, 0, 0)], (std::vector<double>{25, 25, 400, 400}));
  EXPECT_TRUE(
      has(f.recording.import_json, "\"assumed_sigma\":{\"7\":{\"position_m\":5.0,\"velocity_m_s\":2.0}"))
      << f.recording.import_json;
  EXPECT_EQ(f.sensors[1].period, 2.0);
  const CliResult bad = run("import csv -i " + path("g.csv") + " -m " + path("m.json") +
                            " --delimiter ';' --sigma-pos 7:5 --sigma-vel 2 -o " + path("h.h5"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(has(bad.err, "line 4: sensor 9 has no σ for position")) << bad.err;
  const CliResult unknown =
      run("import csv -i " + path("g.csv") + " -m " + path("m.json") +
          " --delimiter ';' --sigma-pos 5 --sigma-vel 2 --sensors 7 -o " + path("h.h5"));
  EXPECT_EQ(unknown.status, 2);
  EXPECT_TRUE(has(unknown.err, "line 4, column 'radar': sensor 9 is not in --sensors")) << unknown.err;
  EXPECT_FALSE(std::filesystem::exists(path("h.h5")));
}

}  // namespace
}  // namespace trackassoc
