// CSV track import and export (io/csv_tracks.hpp) on small CSVs written here: the values read,
// every validation error with its line and column, the WGS-84 → ENU conversion against a
// hand-computed distance, σ-filled covariances, the velocity estimate, and export → import.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "io/csv_tracks.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/geodetic.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

CsvImportOptions cartesian() {
  CsvImportOptions o;
  o.columns =
      parse_csv_mapping(R"({"time": "t", "sensor": "sensor", "track": "track", "x": "x", "y": "y"})", "m");
  return o;
}

TrackFile import_text(const std::string& text, const CsvImportOptions& o, CsvImportSummary* s = nullptr) {
  std::istringstream in(text);
  return import_csv_tracks(in, "t.csv", o, s);
}

// The InputError message of importing `text`, "" if it imports.
std::string error_of(const std::string& text, const CsvImportOptions& o) {
  try {
    import_text(text, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(CsvImport, ReadsColumnsByNameWithVelocityAndPackedCovariance) {
  CsvImportOptions o = cartesian();
  o.columns.vx = "vx";
  o.columns.vy = "vy";
  o.columns.truth = "target";
  o.columns.cov = {"c00", "c01", "c02", "c03", "c11", "c12", "c13", "c22", "c23", "c33"};
  o.period =
      parse_per_sensor_value("1:2", "--period");  // sensor 1 reports once: no interval to estimate from
  // Columns in another order than the state, one unmapped column, spaces after the delimiter.
  const std::string csv =
      "note,track,sensor,t,y,x,vy,vx,c00,c01,c02,c03,c11,c12,c13,c22,c23,c33,target\n"
      "a,4,2,10.0,200,100,-1,5,9,1,0,0,16,0,0,1,0,4,7\n"
      "b,4,2,12.5,197.5,112.5,-1,5,9,1,0,0,16,0,0,1,0,4,7\n"
      "c,0,1, 11,  -3e2, 0.25,0,0,1,0,0,0,1,0,0,1,0,1,-1\n"
      "\n";
  CsvImportSummary s;
  const TrackFile f = import_text(csv, o, &s);
  ASSERT_EQ(f.tracks.size(), 3u);
  EXPECT_EQ(f.tracks.layout, StateLayout::kXY_VXVY);
  EXPECT_EQ(f.tracks.sensor, (std::vector<int32_t>{2, 2, 1}));
  EXPECT_EQ(f.tracks.track, (std::vector<int32_t>{4, 4, 0}));
  EXPECT_EQ(f.tracks.t, (std::vector<double>{10.0, 12.5, 11.0}));
  EXPECT_EQ(f.tracks.state[0], (std::vector<double>{100, 112.5, 0.25}));
  EXPECT_EQ(f.tracks.state[1], (std::vector<double>{200, 197.5, -300}));
  EXPECT_EQ(f.tracks.state[2], (std::vector<double>{5, 5, 0}));
  EXPECT_EQ(f.tracks.cov[1], (std::vector<double>{1, 1, 0}));  // (x, y)
  EXPECT_EQ(f.tracks.cov[4], (std::vector<double>{16, 16, 1}));
  EXPECT_EQ(f.tracks.truth, (std::vector<int32_t>{7, 7, -1}));
  ASSERT_EQ(f.sensors.size(), 2u);  // ascending ids
  EXPECT_EQ(f.sensors[0].id, 1);
  EXPECT_EQ(f.sensors[0].period, 2.0);  // given
  EXPECT_EQ(f.sensors[1].id, 2);
  EXPECT_EQ(f.sensors[1].period, 2.5);  // the one interval of sensor 2
  EXPECT_EQ(s.velocity, "columns");
  EXPECT_EQ(s.covariance, "columns");
  EXPECT_TRUE(f.recording.frame.empty());
  EXPECT_FALSE(f.recording.frame_origin);
  EXPECT_TRUE(has(f.recording.sensors_unknown, "position"));
}

TEST(CsvImport, SensorWithSingleReportsNeedsPeriod) {
  CsvImportOptions o = cartesian();
  o.sigma_position = parse_per_sensor_value("5", "--sigma-pos");
  o.sigma_velocity = parse_per_sensor_value("1", "--sigma-vel");
  const std::string csv = "t,sensor,track,x,y\n0,1,0,0,0\n";
  EXPECT_TRUE(has(error_of(csv, o), "sensor 1: no track of it reports twice")) << error_of(csv, o);
  o.period = parse_per_sensor_value("1:2", "--period");
  EXPECT_EQ(import_text(csv, o).sensors[0].period, 2.0);
}

// Each kind of bad value, with its 1-based line (the header is line 1) and its column.
TEST(CsvImport, EveryBadValueNamesLineAndColumn) {
  CsvImportOptions o = cartesian();
  o.columns.sigma = {{"x", "sx"}, {"y", "sy"}, {"vx", "sv"}, {"vy", "sv2"}};
  const std::string header = "t,sensor,track,x,y,sx,sy,sv,sv2\n";
  const std::string good = "0,1,0,10,20,5,5,1,1\n";
  o.period = parse_per_sensor_value("1", "--period");  // most cases have one good report per track
  struct Case {
    std::string row, expected;
  };
  const Case cases[] = {
      {"1,1,0,abc,20,5,5,1,1\n", "t.csv: line 3, column 'x': expected a number, found 'abc'"},
      {"1,1,0,nan,20,5,5,1,1\n", "line 3, column 'x': expected a finite number, found 'nan'"},
      {"1,1,0,10,-inf,5,5,1,1\n", "line 3, column 'y': expected a finite number, found '-inf'"},
      {"1,1,0,10,20,5,5,1\n", "line 3: 8 fields, the header has 9 (missing fields)"},
      {"1,1,0,10,20,5,5,1,1,9\n", "line 3: 10 fields, the header has 9 (extra fields)"},
      {"1,1,0,,20,5,5,1,1\n", "line 3, column 'x': empty field, expected a number"},
      {"1,1,0.5,10,20,5,5,1,1\n", "line 3, column 'track': expected an integer, found '0.5'"},
      {"1,1,-2,10,20,5,5,1,1\n", "line 3, column 'track': expected a track number >= 0, found -2"},
      {"1,x1,0,10,20,5,5,1,1\n", "line 3, column 'sensor': expected an integer, found 'x1'"},
      {"1,1,0,10,20,0,5,1,1\n", "line 3, column 'sx': expected a σ > 0, found 0"},
      {"-1,1,0,10,20,5,5,1,1\n",
       "line 3, column 't': time -1 is before the previous report of sensor 1, track 0 (t = 0 at line 2)"},
      {"0,1,0,11,20,5,5,1,1\n",
       "line 3, column 't': sensor 1, track 0, t = 0 is also line 2 (a duplicate report)"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(header + good + c.row, o);
    EXPECT_TRUE(has(e, c.expected)) << "expected '" << c.expected << "' in: " << e;
  }
  // Another track of the same sensor may report at the same time; another sensor too.
  EXPECT_EQ(error_of(header + good + "0,1,1,10,20,5,5,1,1\n0,2,0,10,20,5,5,1,1\n", o), "");
  // Sensors not in the list the user gave.
  o.sensors = {1, 3};
  o.period = parse_per_sensor_value("1", "--period");
  EXPECT_TRUE(has(error_of(header + good + "1,2,0,10,20,5,5,1,1\n", o),
                  "line 3, column 'sensor': sensor 2 is not in --sensors"));
  // Every error is counted and listed, not only the first.
  const std::string e = error_of(header + "0,1,0,a,20,5,5,1,1\n0,1,0,10,b,5,5,1,1\n0,1,0,10,20,5,5,1\n", o);
  EXPECT_TRUE(has(e, "t.csv: 3 bad values: line 2, column 'x'")) << e;
  EXPECT_TRUE(has(e, "; line 3, column 'y'")) << e;
  EXPECT_TRUE(has(e, "; line 4: 8 fields")) << e;
  o.max_errors = 2;
  EXPECT_TRUE(has(error_of(header + "0,1,0,a,20,5,5,1,1\n0,1,0,10,b,5,5,1,1\n0,1,0,10,20,5,5,1\n", o),
                  "3 bad values (the first 2)"));
}

TEST(CsvImport, CovarianceColumnsMustBePositiveDefinite) {
  CsvImportOptions o = cartesian();
  o.columns.vx = "vx";
  o.columns.vy = "vy";
  o.columns.cov = {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j"};
  const std::string csv =
      "t,sensor,track,x,y,vx,vy,a,b,c,d,e,f,g,h,i,j\n"
      "0,1,0,0,0,0,0,1,2,0,0,1,0,0,1,0,1\n";  // |ρ(x,y)| = 2 > 1
  const std::string e = error_of(csv, o);
  EXPECT_TRUE(has(e, "line 2, column 'a'..'j': the covariance is not positive definite: Cholesky pivot 1"))
      << e;
}

TEST(CsvImport, MappingErrorsNameTheKey) {
  EXPECT_TRUE(has(error_of("t\n", CsvImportOptions{}), "mapping: key 'time' is required"));
  CsvImportOptions o = cartesian();
  o.columns.lat = "lat";
  EXPECT_TRUE(has(error_of("t\n", o), "x, y[, z] or lat, lon[, alt], not both"));
  o = cartesian();
  o.columns.vx = "vx";
  EXPECT_TRUE(has(error_of("t\n", o), "give both 'vx' and 'vy'"));
  o = cartesian();
  o.columns.cov = {"a", "b"};
  EXPECT_TRUE(has(error_of("t\n", o), "key 'cov': expected 10 columns"));
  o = cartesian();
  o.columns.x = "east";
  EXPECT_TRUE(
      has(error_of("t,sensor,track,x,y\n", o),
          "t.csv: mapping key 'x': column 'east' is not in the header (line 1: t, sensor, track, x, y"));
  EXPECT_TRUE(has(error_of("t;sensor;track;x;y\n", cartesian()), "is the delimiter ';'?"));
  auto json_error = [](const std::string& text) {
    try {
      parse_csv_mapping(text, "m.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_TRUE(
      has(json_error(R"({"time": "t", "vleocity": "v"})"), "m.json: mapping key 'vleocity' is unknown"));
  EXPECT_TRUE(has(json_error(R"({"time": 3})"), "mapping key 'time': expected a column name"));
  EXPECT_TRUE(has(json_error(R"({"cov": "c"})"), "mapping key 'cov': expected an array"));
  EXPECT_TRUE(has(json_error(R"({"time": "t", "time": "u"})"), "key 'time' appears twice"));
  EXPECT_TRUE(has(json_error(R"({"time": "t",)"), "m.json: invalid JSON"));
  const CsvColumnMapping m = parse_csv_mapping(R"({"time": "t", "sigma": {"x": "sx"}, "cov": []})", "m.json");
  EXPECT_EQ(m.time, "t");
  EXPECT_EQ(m.sigma.at("x"), "sx");
  EXPECT_EQ(parse_csv_mapping(csv_mapping_to_json(csv_export_mapping(StateLayout::kXYZ_VXVYVZ)), "x"),
            csv_export_mapping(StateLayout::kXYZ_VXVYVZ));
}

// The WGS-84 meridian radius of curvature at φ = 63.4° (computed by hand from a = 6 378 137 m,
// f = 1/298.257223563, e² = f(2 − f) = 0.00669437999):
//   M = a(1 − e²) / (1 − e² sin²φ)^{3/2} = 6 335 439.327 / 0.991983 = 6 386 644.90 m,
// so 0.001° of latitude (1.7453293e-5 rad) is 111.4680 m north; the prime-vertical radius
// N = a / (1 − e² sin²φ)^{1/2} = 6 395 274.47 m makes 0.001° of longitude N cos φ · Δλ = 49.9782 m
// east. (A sphere of radius 6 371 km would give 111.19 m: the ellipsoid matters at this latitude.)
TEST(CsvImport, GeodeticToEnuMatchesTheMeridianRadius) {
  CsvImportOptions o;
  o.columns.time = "t";
  o.columns.sensor = "s";
  o.columns.track = "k";
  o.columns.lat = "lat";
  o.columns.lon = "lon";
  o.sigma_position = parse_per_sensor_value("3", "--sigma-pos");
  o.sigma_velocity = parse_per_sensor_value("1", "--sigma-vel");
  o.origin = parse_geodetic_origin("63.4,10.4", "--origin");
  const std::string csv = "t,s,k,lat,lon\n0,1,0,63.401,10.4\n1,1,0,63.4,10.401\n";
  const TrackFile f = import_text(csv, o);
  EXPECT_EQ(f.tracks.layout, StateLayout::kXY_VXVY);
  EXPECT_NEAR(f.tracks.state[0][0], 0.0, 1e-6);       // east
  EXPECT_NEAR(f.tracks.state[1][0], 111.4680, 2e-3);  // north
  EXPECT_NEAR(f.tracks.state[0][1], 49.9782, 2e-3);
  EXPECT_NEAR(f.tracks.state[1][1], 0.0, 2e-3);  // the parallel curves away from the tangent plane's north
  EXPECT_EQ(f.recording.frame, "ENU");
  ASSERT_TRUE(f.recording.frame_origin);
  EXPECT_EQ(*f.recording.frame_origin, (std::array<double, 3>{63.4, 10.4, 0.0}));
  // With alt: 3-D; without --origin the first report is the origin.
  o.columns.alt = "h";
  o.origin.reset();
  const TrackFile g = import_text("t,s,k,lat,lon,h\n0,1,0,63.4,10.4,20\n1,1,0,63.401,10.4,30\n", o);
  EXPECT_EQ(g.tracks.layout, StateLayout::kXYZ_VXVYVZ);
  EXPECT_EQ(*g.recording.frame_origin, (std::array<double, 3>{63.4, 10.4, 20.0}));
  EXPECT_NEAR(g.tracks.state[1][0], 0.0, 1e-9);
  EXPECT_NEAR(g.tracks.state[1][1], 111.4680, 2e-3);
  EXPECT_NEAR(g.tracks.state[2][1], 10.0 - 111.468 * 111.468 / (2 * 6.39e6), 1e-3);  // up: 10 m less the drop
  EXPECT_TRUE(has(error_of("t,s,k,lat,lon,h\n0,1,0,91,10.4,20\n", o),
                  "line 2, column 'lat': expected a latitude in [-90, 90] degrees, found 91"));
}

TEST(CsvImport, SigmaFlagsFillTheCovarianceAndAreStated) {
  CsvImportOptions o = cartesian();
  o.columns.vx = "vx";
  o.columns.vy = "vy";
  o.columns.sigma = {{"x", "sx"}};  // σ_x from a column, the rest from the flags
  o.sigma_position = parse_per_sensor_value("1:5,2:20", "--sigma-pos");
  o.sigma_velocity = parse_per_sensor_value("2", "--sigma-vel");
  const std::string csv =
      "t,sensor,track,x,y,vx,vy,sx\n0,1,0,0,0,1,1,3\n1,1,0,1,1,1,1,3\n0,2,0,0,0,1,1,4\n2,2,0,2,2,1,1,4\n";
  CsvImportSummary s;
  const TrackFile f = import_text(csv, o, &s);
  const int d = 4;
  EXPECT_EQ(f.tracks.cov[packed_index(d, 0, 0)], (std::vector<double>{9, 9, 16, 16}));
  EXPECT_EQ(f.tracks.cov[packed_index(d, 1, 1)], (std::vector<double>{25, 25, 400, 400}));
  EXPECT_EQ(f.tracks.cov[packed_index(d, 2, 2)], (std::vector<double>{4, 4, 4, 4}));
  EXPECT_EQ(f.tracks.cov[packed_index(d, 0, 1)], (std::vector<double>{0, 0, 0, 0}));
  EXPECT_EQ(s.covariance, "sigma columns and assumed (--sigma-pos/--sigma-vel)");
  const auto info = nlohmann::json::parse(f.recording.import_json);
  EXPECT_EQ(info["assumed_sigma"]["1"]["position_m"], 5.0);
  EXPECT_EQ(info["assumed_sigma"]["2"]["position_m"], 20.0);
  EXPECT_EQ(info["assumed_sigma"]["2"]["velocity_m_s"], 2.0);
  EXPECT_EQ(f.sensors[1].period, 2.0);
  // A sensor with no σ at all: named once, with the flag to give.
  o.sigma_position = parse_per_sensor_value("1:5", "--sigma-pos");
  const std::string e = error_of(csv, o);
  EXPECT_TRUE(has(e, "line 4: sensor 2 has no σ for position")) << e;
  EXPECT_TRUE(has(e, "--sigma-pos")) << e;
  EXPECT_FALSE(has(e, "line 5")) << e;
}

// x = 3 + 2t + t²/2 at the uneven times 0, 1, 3, 4: the three-point derivative is exact for a
// parabola, v = 2 + t (3 at t = 1, 5 at t = 3); the ends are one-sided: (5.5 − 3)/1 = 2.5 at
// t = 0 and (19 − 13.5)/1 = 5.5 at t = 4. y = 7 − t: v_y = −1 everywhere.
TEST(CsvImport, EstimatesVelocityByTheThreePointDerivative) {
  CsvImportOptions o = cartesian();
  o.sigma_position = parse_per_sensor_value("1", "--sigma-pos");
  o.sigma_velocity = parse_per_sensor_value("1", "--sigma-vel");
  const std::string csv = "t,sensor,track,x,y\n0,1,0,3,7\n0,1,5,9,9\n1,1,0,5.5,6\n3,1,0,13.5,4\n4,1,0,19,3\n";
  CsvImportSummary s;
  const TrackFile f = import_text(csv, o, &s);
  EXPECT_EQ(s.velocity, "estimated (three-point derivative per track)");
  const std::vector<double> vx = {2.5, 0.0, 3.0, 5.0, 5.5};  // track 5 has one report: 0
  for (std::size_t r = 0; r < vx.size(); ++r) {
    EXPECT_NEAR(f.tracks.state[2][r], vx[r], 1e-12) << r;
    EXPECT_NEAR(f.tracks.state[3][r], f.tracks.track[r] == 5 ? 0.0 : -1.0, 1e-12) << r;
  }
  EXPECT_EQ(f.sensors[0].period, 1.0);  // intervals 1, 2, 1: the median
}

TEST(CsvImport, DelimitersAndPerSensorValues) {
  CsvImportOptions o = cartesian();
  o.sigma_position = parse_per_sensor_value("10,3:1", "--sigma-pos");
  EXPECT_EQ(*o.sigma_position.for_sensor(3), 1.0);
  EXPECT_EQ(*o.sigma_position.for_sensor(4), 10.0);
  o.sigma_velocity = parse_per_sensor_value("1", "--sigma-vel");
  o.delimiter = parse_csv_delimiter("tab", "--delimiter");
  EXPECT_EQ(import_text("t\tsensor\ttrack\tx\ty\r\n0\t3\t0\t1\t2\r\n1\t3\t0\t2\t2\r\n", o).tracks.state[0][1],
            2.0);
  o.delimiter = ';';
  EXPECT_EQ(import_text("t;sensor;track;x;y\n0;3;0;1.5;2\n1;3;0;2;2\n", o).tracks.state[0][0], 1.5);
  // A decimal comma is one field with ';', and not a number.
  EXPECT_TRUE(has(error_of("t;sensor;track;x;y\n0;3;0;1,5;2\n", o),
                  "line 2, column 'x': expected a number, found '1,5'"));
}

TEST(CsvImport, QuotedFieldsMayHoldTheDelimiter) {
  CsvImportOptions o = cartesian();
  o.sigma_position = parse_per_sensor_value("10", "--sigma-pos");
  o.sigma_velocity = parse_per_sensor_value("1", "--sigma-vel");
  // A quoted header, a quoted number, and an unmapped text column with the delimiter and a ""
  // inside its quotes: still 6 fields a row.
  const std::string csv =
      "\"t\",\"sensor\",track,x,\"y\",note\n"
      "0,3,0,\"1.5\",2,\"harbour, quay \"\"B\"\"\"\n"
      "1,3,0, \"2.5\" ,2,plain\n";
  const TrackFile f = import_text(csv, o);
  ASSERT_EQ(f.tracks.size(), 2u);
  EXPECT_EQ(f.tracks.state[0][0], 1.5);
  EXPECT_EQ(f.tracks.state[0][1], 2.5);
  // An unclosed quote, or text after the closing quote, names the line.
  EXPECT_TRUE(has(error_of("t,sensor,track,x,y\n0,3,0,1,2\n1,3,0,\"2,2\n", o),
                  "line 3: a quoted field without its closing quote"));
  EXPECT_TRUE(has(error_of("t,sensor,track,x,y\n0,3,0,\"1\"x,2\n", o), "line 2: a quoted field"));
  EXPECT_TRUE(has(error_of("\"t,sensor,track,x,y\n0,3,0,1,2\n", o), "line 1 (the header)"));
  // An empty quoted field, a quoted last field before \r\n, and with tabs: an empty field before a
  // quoted one is still a field (the blanks skipped before a quote are not the delimiter).
  const std::string with_note = "t,sensor,track,x,y,note\n0,3,0,1,2,\"\"\n1,3,0,2,2,\"q\"\r\n";
  EXPECT_EQ(import_text(with_note, o).tracks.size(), 2u);
  o.delimiter = '\t';
  const TrackFile tabs =
      import_text("t\tsensor\ttrack\tnote\tx\ty\n0\t3\t0\t\t\"1\"\t2\n1\t3\t0\t\t4\t2\n", o);
  ASSERT_EQ(tabs.tracks.size(), 2u);
  EXPECT_EQ(tabs.tracks.state[0][0], 1.0);
}

TEST(CsvImport, ExportThenImportGivesTheSameTracksAndFileAttributes) {
  TempDir dir;
  TrackFile a;
  a.tracks.reset(StateLayout::kXYZ_VXVYVZ);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(6, 6) * 2.0;
  P(0, 1) = P(1, 0) = 0.1 / 3.0;
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd x(6);
    x << 1.0 / 3.0 + k, -2e7 + k * 0.1, 1e-9, 0.7, -0.3, 0.1 * k;
    a.tracks.push_back(k % 2, 3, 0.1 * k, x, P, k % 2 ? -1 : 4);
  }
  a.sensors.resize(2);
  a.sensors[1].id = 1;
  write_csv_tracks(dir.file("t.csv"), a);
  CsvImportOptions o;
  o.columns = csv_export_mapping(StateLayout::kXYZ_VXVYVZ);
  const TrackFile b = import_csv_tracks_file(dir.file("t.csv"), o);
  EXPECT_EQ(b.tracks.sensor, a.tracks.sensor);
  EXPECT_EQ(b.tracks.t, a.tracks.t);
  EXPECT_EQ(b.tracks.state, a.tracks.state);  // bit for bit: shortest round-trip text
  EXPECT_EQ(b.tracks.cov, a.tracks.cov);
  EXPECT_EQ(b.tracks.truth, a.tracks.truth);
  // The HDF5 file keeps the recording attributes; the reader accepts them.
  write_track_file(dir.file("b.h5"), b);
  const TrackFile c = read_track_file_in_process(dir.file("b.h5"));
  EXPECT_EQ(c.recording, b.recording);
  EXPECT_FALSE(c.recording.import_json.empty());
  EXPECT_EQ(c.sensors[1].period, 0.2);
}

TEST(CsvImport, TrackFileReaderChecksTheFrameAttributes) {
  TempDir dir;
  TrackFile f;
  f.sensors.resize(1);
  f.recording.frame = "ENU";
  f.recording.frame_origin = std::array<double, 3>{63.4, 10.4, 0.0};
  write_track_file(dir.file("f.h5"), f);
  EXPECT_EQ(read_track_file_in_process(dir.file("f.h5")).recording, f.recording);
  f.recording.frame = "ECEF";
  EXPECT_THROW(write_track_file(dir.file("g.h5"), f), InputError);
  f.recording.frame = "ENU";
  f.recording.frame_origin = std::array<double, 3>{95, 0, 0};
  EXPECT_THROW(write_track_file(dir.file("g.h5"), f), InputError);
}

TEST(Geodetic, EnuOfTheOriginIsZeroAndEcefMatchesTheEquator) {
  const auto p = geodetic_to_ecef(0, 90, 0);
  EXPECT_NEAR(p[0], 0.0, 1e-6);
  EXPECT_NEAR(p[1], kWgs84A, 1e-6);
  const EnuFrame frame(-33.9, 151.2, 50);
  const auto e = frame.enu(-33.9, 151.2, 50);
  for (double v : e) EXPECT_NEAR(v, 0.0, 1e-6);
  EXPECT_NEAR(frame.enu(-33.9, 151.2, 150)[2], 100.0, 1e-6);  // up is up
}

}  // namespace
}  // namespace trackassoc
