// Bad input to the HDF5 reader (docs/design.md §7): each case gives an InputError whose message names
// the file, the dataset (and row) and what is wrong. Files are damaged with the raw HDF5 C API
// after a valid write, so they are files our writer would never produce.
#include <chrono>
#include <random>
#include <thread>

#include "io/isolated_run.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

class BadTrackFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.file("in.h5");
    write_track_file(path_, test::full_track_file(StateLayout::kXY_VXVY));
    rows_ = test::full_track_file(StateLayout::kXY_VXVY).tracks.size();
  }
  // Damages the file, then expects read_track_file to fail with a message naming the file and
  // containing `expected`.
  void expect_error(const std::function<void(hid_t)>& damage, const std::string& expected) {
    test::damage_file(path_, damage);
    expect_error(expected);
  }
  void expect_error(const std::string& expected) {
    const std::string msg = test::read_error(path_);
    EXPECT_NE(msg.find(expected), std::string::npos) << "message: " << msg << "\nexpected: " << expected;
    EXPECT_EQ(msg.rfind(path_ + ": ", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
  TempDir dir_;
  std::string path_;
  hsize_t rows_ = 0;
};

TEST_F(BadTrackFile, EmptyFile) {
  test::write_bytes(path_, "");
  expect_error("empty file");
}

TEST_F(BadTrackFile, MissingFile) {
  std::filesystem::remove(path_);
  expect_error("does not exist");
}

TEST_F(BadTrackFile, RandomBytes) {
  std::mt19937_64 rng(7);
  std::string bytes(4096, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  test::write_bytes(path_, bytes);
  expect_error("not an HDF5 file");
}

TEST_F(BadTrackFile, RandomBytesAfterAnHdf5Signature) {
  std::mt19937_64 rng(8);
  std::string bytes = std::string("\x89HDF\r\n\x1a\n", 8) + std::string(4088, '\0');
  for (std::size_t i = 8; i < bytes.size(); ++i) bytes[i] = static_cast<char>(rng());
  test::write_bytes(path_, bytes);
  const std::string msg = test::read_error(path_);
  EXPECT_EQ(msg.rfind(path_ + ": ", 0), 0u) << msg;
}

TEST_F(BadTrackFile, TruncatedFiles) {
  const std::string whole = test::file_bytes(path_);
  // Every cut point would be slow; these cover the superblock, object headers and raw data.
  for (std::size_t cut : {std::size_t{8}, std::size_t{100}, whole.size() / 4, whole.size() / 2,
                          whole.size() - 100, whole.size() - 1}) {
    test::write_bytes(path_, whole.substr(0, cut));
    const std::string msg = test::read_error(path_);
    EXPECT_NE(msg, "no error") << "cut at " << cut;
    EXPECT_EQ(msg.rfind(path_ + ": ", 0), 0u) << msg;
  }
}

TEST_F(BadTrackFile, MissingTracks) {
  expect_error([](hid_t f) { H5Ldelete(f, "/tracks", H5P_DEFAULT); }, "/tracks: missing group (required)");
}

TEST_F(BadTrackFile, MissingSensors) {
  expect_error([](hid_t f) { H5Ldelete(f, "/sensors", H5P_DEFAULT); }, "/sensors: missing group (required)");
}

TEST_F(BadTrackFile, MissingCovarianceDataset) {
  expect_error([](hid_t f) { H5Ldelete(f, "/tracks/cov", H5P_DEFAULT); }, "/tracks/cov: missing dataset");
}

TEST_F(BadTrackFile, WrongFormatAttribute) {
  expect_error([](hid_t f) { test::put_string_attribute(f, "/", "format", "netcdf"); },
               "/ attribute format: expected \"trackassoc\", found \"netcdf\"");
}

TEST_F(BadTrackFile, MissingFormatAttribute) {
  expect_error([](hid_t f) { H5Adelete(f, "format"); }, "not a trackassoc file");
}

TEST_F(BadTrackFile, WrongSchemaVersion) {
  expect_error([](hid_t f) { test::put_int_attribute(f, "/", "schema_version", 2); },
               "schema_version: expected 1, found 2");
}

TEST_F(BadTrackFile, SchemaVersionAsString) {
  expect_error([](hid_t f) { test::put_string_attribute(f, "/", "schema_version", "1"); },
               "attribute schema_version: expected an integer, found string");
}

TEST_F(BadTrackFile, UnknownStateLayout) {
  expect_error([](hid_t f) { test::put_string_attribute(f, "/tracks", "state_layout", "x,y"); },
               "/tracks attribute state_layout: expected \"x,y,vx,vy\" or \"x,y,z,vx,vy,vz\", found \"x,y\"");
}

TEST_F(BadTrackFile, StateWithTheWrongNumberOfColumns) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<double> v(n * 5, 1.0);
        test::put_dataset(f, "/tracks/state", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, 5}, v.data());
      },
      "/tracks/state: expected shape " + std::to_string(n) + "x4");
}

TEST_F(BadTrackFile, CovarianceWithTheWrongNumberOfColumns) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<double> v(n * 16, 1.0);  // a full 4×4 instead of the packed 10
        test::put_dataset(f, "/tracks/cov", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, 16}, v.data());
      },
      "/tracks/cov: expected shape " + std::to_string(n) + "x10");
}

TEST_F(BadTrackFile, ColumnLengthsDisagree) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<double> v(n - 1, 1.0);
        test::put_dataset(f, "/tracks/t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n - 1}, v.data());
      },
      "/tracks/t: expected " + std::to_string(n) + " rows (as /tracks/sensor), found " +
          std::to_string(n - 1));
}

TEST_F(BadTrackFile, TwoDimensionalWhereOneIsExpected) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<double> v(n, 1.0);
        test::put_dataset(f, "/tracks/t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, 1}, v.data());
      },
      "/tracks/t: expected a 1-D dataset, found shape " + std::to_string(n) + "x1");
}

TEST_F(BadTrackFile, StringsWhereNumbersAreExpected) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        const hid_t type = H5Tcopy(H5T_C_S1);
        H5Tset_size(type, 4);
        std::vector<char> v(n * 4, 'a');
        test::put_dataset(f, "/tracks/t", type, type, {n}, v.data());
        H5Tclose(type);
      },
      "/tracks/t: expected numeric (integer or float) values, found string");
}

TEST_F(BadTrackFile, FloatsWhereIntegersAreExpected) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<double> v(n, 10.0);
        test::put_dataset(f, "/tracks/sensor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n}, v.data());
      },
      "/tracks/sensor: expected integer values, found float");
}

TEST_F(BadTrackFile, OtherIntegerAndFloatWidthsAreConverted) {
  const TrackFile original = read_track_file(path_);
  const hsize_t n = rows_;
  test::damage_file(path_, [&](hid_t f) {
    std::vector<int64_t> sensor(original.tracks.sensor.begin(), original.tracks.sensor.end());
    test::put_dataset(f, "/tracks/sensor", H5T_STD_I64BE, H5T_NATIVE_INT64, {n}, sensor.data());
    std::vector<int16_t> track(original.tracks.track.begin(), original.tracks.track.end());
    test::put_dataset(f, "/tracks/track", H5T_STD_U16LE, H5T_NATIVE_INT16, {n}, track.data());
    std::vector<float> t(original.tracks.t.begin(), original.tracks.t.end());  // 0, 2, 4, 6: exact in float
    test::put_dataset(f, "/tracks/t", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, {n}, t.data());
  });
  const TrackFile back = read_track_file(path_);
  EXPECT_EQ(back.tracks.sensor, original.tracks.sensor);
  EXPECT_EQ(back.tracks.track, original.tracks.track);
  EXPECT_EQ(back.tracks.t, original.tracks.t);
}

// Strings as other writers store them: variable-length (h5py's str) and fixed-length ASCII.
TEST_F(BadTrackFile, VariableAndFixedLengthStringAttributesFromOtherWritersAreRead) {
  test::damage_file(path_, [](hid_t f) {
    test::put_vlen_string_attribute(f, "/", "created_by", "h5py 3.7 \u00e9");
    test::put_vlen_string_attribute(f, "/tracks", "state_layout", "x,y,vx,vy");
    test::put_string_attribute(f, "/", "format", "trackassoc");
  });
  const TrackFile back = read_track_file(path_);
  EXPECT_EQ(back.created_by, "h5py 3.7 \u00e9");
  EXPECT_EQ(back.tracks.layout, StateLayout::kXY_VXVY);
}

TEST_F(BadTrackFile, IntegerTooWideForInt32) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<int64_t> v(n, 10);
        v[3] = int64_t{1} << 40;
        test::put_dataset(f, "/tracks/track", H5T_STD_I64LE, H5T_NATIVE_INT64, {n}, v.data());
      },
      "/tracks/track: row 3: value 1099511627776 does not fit int32");
}

// Overwrites one element of a 2-D double dataset.
std::function<void(hid_t)> set_element(const std::string& name, std::size_t index, double value) {
  return [=](hid_t f) {
    std::vector<double> v = test::read_all_doubles(f, name);
    v[index] = value;
    const hid_t set = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(set);
  };
}

TEST_F(BadTrackFile, NaNInState) {
  expect_error(set_element("/tracks/state", 3 * 4 + 2, std::nan("")),
               "/tracks/state: row 3: column 2 (vx): expected a finite value, found nan");
}

TEST_F(BadTrackFile, InfInTime) {
  expect_error(set_element("/tracks/t", 7, -std::numeric_limits<double>::infinity()),
               "/tracks/t: row 7: expected a finite value, found -inf");
}

TEST_F(BadTrackFile, InfInCovariance) {
  expect_error(set_element("/tracks/cov", 1 * 10 + 4, std::numeric_limits<double>::infinity()),
               "/tracks/cov: row 1: column 4: expected a finite value, found inf");
}

TEST_F(BadTrackFile, NaNInSensorPosition) {
  expect_error(set_element("/sensors/position", 2 * 3 + 1, std::nan("")),
               "/sensors/position: row 2: column 1: expected a finite value, found nan");
}

TEST_F(BadTrackFile, NegativeCovarianceDiagonal) {
  // Packed 4×4 upper triangle: (1,1) is column 4.
  expect_error(
      set_element("/tracks/cov", 6 * 10 + 4, -2.0),
      "/tracks/cov: row 6: covariance is not positive definite: diagonal element (1,1) = -2 is not positive");
}

TEST_F(BadTrackFile, IndefiniteCovarianceWithPositiveDiagonal) {
  // Off-diagonal (0,1) far larger than sqrt(P00·P11): symmetric, positive diagonal, indefinite.
  expect_error(set_element("/tracks/cov", 9 * 10 + 1, 1e6),
               "/tracks/cov: row 9: covariance is not positive definite: Cholesky pivot 1");
}

// Rows 12 and 13 of test::full_track_file are sensor 20, track 2 at t = 0 and t = 2 (row = 12·s +
// 4·(2 - track) + k, t = 2k); t = 0 in row 13 makes them two reports of one track at one time.
TEST_F(BadTrackFile, TwoReportsOfOneTrackAtOneTime) {
  expect_error(set_element("/tracks/t", 13, 0.0),
               "/tracks: row 13: sensor 20, track 2, t = 0 is also row 12 with a different state");
}

TEST(TrackFileWriter, RefusesTwoReportsOfOneTrackAtOneTime) {
  TrackFile f = test::full_track_file(StateLayout::kXY_VXVY);
  f.tracks.t[5] = f.tracks.t[4];  // sensor 10, track 1 (rows 4..7), t = 0 twice
  test::TempDir dir;
  try {
    write_track_file(dir.file("out.h5"), f);
    ADD_FAILURE() << "the writer accepted two reports of one track at one time";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("row 5: sensor 10, track 1, t = 0 is also row 4"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(dir.entries().empty()) << "no file, no .tmp left behind";
}

TEST_F(BadTrackFile, UnknownSensorId) {
  const hsize_t n = rows_;
  expect_error(
      [n](hid_t f) {
        std::vector<int32_t> v(n, 10);
        v[5] = 42;
        test::put_dataset(f, "/tracks/sensor", H5T_STD_I32LE, H5T_NATIVE_INT32, {n}, v.data());
      },
      "/tracks/sensor: row 5: sensor 42 is not in /sensors/id");
}

TEST_F(BadTrackFile, DuplicateSensorId) {
  expect_error(
      [](hid_t f) {
        const int32_t ids[] = {10, 20, 10};
        test::put_dataset(f, "/sensors/id", H5T_STD_I32LE, H5T_NATIVE_INT32, {3}, ids);
      },
      "/sensors/id: row 2: sensor id 10 appears twice");
}

TEST_F(BadTrackFile, SensorDatasetOfTheWrongLength) {
  expect_error(
      [](hid_t f) {
        const double v[] = {1, 2};
        test::put_dataset(f, "/sensors/period", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {2}, v);
      },
      "/sensors/period: expected 3 rows (as /sensors/id), found 2");
}

TEST_F(BadTrackFile, AssociationReferringToAMissingTrack) {
  expect_error(
      [](hid_t f) {
        const int32_t t[] = {0, 2, -1, 1, 7, -1, 2, -1, -1};
        test::put_dataset(f, "/associations/hopfield-sync/tuples", H5T_STD_I32LE, H5T_NATIVE_INT32, {3, 3},
                          t);
      },
      "/associations/hopfield-sync/tuples: row 1: column 1 (sensor 20): expected -1 or a track number");
}

TEST_F(BadTrackFile, MetricsWithoutRates) {
  expect_error([](hid_t f) { H5Adelete_by_name(f, "/metrics/empty", "correct_rate", H5P_DEFAULT); },
               "/metrics/empty attribute correct_rate: missing");
}

// docs/design.md §7 edge cases that are valid input: a silent sensor (zero tracks), and tracks without
// /tracks/truth (a recorded set without ground truth).
TEST_F(BadTrackFile, SensorWithZeroTracksAndNoTruthColumnAreValid) {
  test::damage_file(path_, [](hid_t f) {
    H5Ldelete(f, "/tracks/truth", H5P_DEFAULT);
    H5Ldelete(f, "/truth", H5P_DEFAULT);
    H5Ldelete(f, "/sensors/sigma_elevation", H5P_DEFAULT);  // optional sensor fields default
  });
  const TrackFile f = read_track_file(path_);
  ASSERT_EQ(f.sensors.size(), 3u);
  EXPECT_EQ(std::count(f.tracks.sensor.begin(), f.tracks.sensor.end(), 30), 0);
  EXPECT_EQ(f.tracks.truth, std::vector<int32_t>(f.tracks.size(), -1));
  EXPECT_FALSE(f.truth.has_value());
  EXPECT_EQ(f.sensors[2].sigma_elevation, Sensor{}.sigma_elevation);
}

}  // namespace
}  // namespace trackassoc

namespace trackassoc {
namespace {

// io/isolated_run.hpp: a crash, a hang or an InputError in the child becomes an InputError here.
TEST(IsolatedRun, CrashHangAndErrorInTheChildBecomeInputErrors) {
  EXPECT_NO_THROW(run_isolated(
      "f.h5", [] {}, 10.0));
  try {
    run_isolated(
        "f.h5", [] { throw InputError("f.h5: /tracks/t: row 3: bad"); }, 10.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f.h5: /tracks/t: row 3: bad");
  }
  try {
    run_isolated(
        "f.h5", [] { std::abort(); }, 10.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f.h5: the file is corrupt"), std::string::npos) << e.what();
  }
  const auto start = std::chrono::steady_clock::now();
  try {
    run_isolated(
        "f.h5", [] { std::this_thread::sleep_for(std::chrono::seconds(30)); }, 0.5);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f.h5: reading did not finish within"), std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

// Files found by libFuzzer (tests/fuzz/fuzz_track_file) on which libhdf5 1.10.8 itself hangs
// (global heap), overlaps a memcpy (global heap) or overruns a buffer (attribute message). Read
// through the guard, each is an InputError naming the file; nothing crashes or hangs.
TEST(IsolatedRun, FilesThatBreakLibhdf5AreInputErrors) {
  const std::string dir = std::string(TRACKASSOC_SOURCE_DIR) + "/tests/fuzz/regressions/";
  for (const char* name :
       {"hdf5_hang_global_heap.h5", "hdf5_overlap_global_heap.h5", "hdf5_overflow_attribute_header.h5"}) {
    const std::string path = dir + name;
    try {
      read_track_file(path, 3.0);
      ADD_FAILURE() << name << " was read without error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace trackassoc
