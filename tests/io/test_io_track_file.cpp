// HDF5 schema v1 (io/track_file.hpp): exact round trips of every group in 2-D and 3-D, the
// layout of the file as h5py sees it, bit-identical output for the same content, and atomic
// writes that never damage an existing file.
#include <chrono>
#include <cstdlib>
#include <thread>

#include "io/hdf5_wrapper.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

class RoundTrip : public ::testing::TestWithParam<StateLayout> {};

TEST_P(RoundTrip, EveryValueOfAFullFileComesBackExactly) {
  TempDir dir;
  const TrackFile f = test::full_track_file(GetParam());
  const std::string path = dir.file("full.h5");
  write_track_file(path, f);
  const TrackFile back = read_track_file(path);
  test::expect_same_file(f, back);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"full.h5"});  // no .tmp left behind
}

TEST_P(RoundTrip, MinimalFileWithOnlySensorsAndTracks) {
  TempDir dir;
  TrackFile f = test::full_track_file(GetParam(), /*all_sensors=*/true);
  f.truth.reset();
  f.measurements.reset();
  f.associations.clear();
  f.metrics.clear();
  f.scenario_json.clear();
  write_track_file(dir.file("min.h5"), f);
  test::expect_same_file(f, read_track_file(dir.file("min.h5")));
}

TEST_P(RoundTrip, EmptyTrackTableAndNoSensorsWithTracks) {
  TempDir dir;
  TrackFile f = test::full_track_file(GetParam());
  f.tracks.reset(GetParam());  // n = 0 rows
  f.associations.resize(1);
  f.associations[0].tuples.clear();
  f.associations[0].cost.clear();
  f.measurements->sensor.clear();
  f.measurements->t.clear();
  f.measurements->range.clear();
  f.measurements->bearing.clear();
  f.measurements->elevation.clear();
  f.measurements->target.clear();
  write_track_file(dir.file("empty.h5"), f);
  test::expect_same_file(f, read_track_file(dir.file("empty.h5")));
}

INSTANTIATE_TEST_SUITE_P(Layouts, RoundTrip,
                         ::testing::Values(StateLayout::kXY_VXVY, StateLayout::kXYZ_VXVYVZ),
                         [](const auto& info) { return info.param == StateLayout::kXY_VXVY ? "2D" : "3D"; });

// The file as another program sees it: dataset shapes, dtypes and the row-major packing of state
// and covariance (checked against TrackTable::cov_at, not against the writer's own helper).
TEST(TrackFileLayout, DatasetsHaveTheSchemaShapesAndRowMajorPacking) {
  TempDir dir;
  const TrackFile f = test::full_track_file(StateLayout::kXYZ_VXVYVZ);
  write_track_file(dir.file("f.h5"), f);
  const hid_t h = H5Fopen(dir.file("f.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h, 0);
  auto shape = [&](const char* name) {
    const hid_t set = H5Dopen2(h, name, H5P_DEFAULT);
    const hid_t space = H5Dget_space(set);
    std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(space));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    H5Sclose(space);
    H5Dclose(set);
    return dims;
  };
  const hsize_t n = f.tracks.size();
  EXPECT_EQ(shape("/tracks/state"), (std::vector<hsize_t>{n, 6}));
  EXPECT_EQ(shape("/tracks/cov"), (std::vector<hsize_t>{n, 21}));
  EXPECT_EQ(shape("/sensors/position"), (std::vector<hsize_t>{3, 3}));
  EXPECT_EQ(shape("/associations/hopfield-sync/tuples"), (std::vector<hsize_t>{3, 3}));
  EXPECT_EQ(shape("/associations/hopfield-sync/energy"), (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(shape("/associations/greedy/tuples"), (std::vector<hsize_t>{0, 3}));
  const std::vector<double> cov = test::read_all_doubles(h, "/tracks/cov");
  const std::size_t row = 5;
  const Eigen::MatrixXd p = f.tracks.cov_at(row);
  EXPECT_EQ(cov[row * 21 + 0], p(0, 0));
  EXPECT_EQ(cov[row * 21 + 1], p(0, 1));
  EXPECT_EQ(cov[row * 21 + 5], p(0, 5));
  EXPECT_EQ(cov[row * 21 + 6], p(1, 1));
  EXPECT_EQ(cov[row * 21 + 20], p(5, 5));
  const std::vector<double> state = test::read_all_doubles(h, "/tracks/state");
  EXPECT_EQ(state[row * 6 + 4], f.tracks.state_at(row)[4]);
  // dtypes: int32 ids, float64 values, float32 energy.
  auto dtype_size = [&](const char* name) {
    const hid_t set = H5Dopen2(h, name, H5P_DEFAULT);
    const hid_t type = H5Dget_type(set);
    const std::size_t s = H5Tget_size(type);
    H5Tclose(type);
    H5Dclose(set);
    return s;
  };
  EXPECT_EQ(dtype_size("/tracks/sensor"), 4u);
  EXPECT_EQ(dtype_size("/tracks/t"), 8u);
  EXPECT_EQ(dtype_size("/associations/hopfield-sync/energy"), 4u);
  H5Fclose(h);
}

TEST(TrackFileLayout, AssociationsAndMetricsKeepTheirOrder) {
  TempDir dir;
  TrackFile f = test::full_track_file(StateLayout::kXY_VXVY);
  std::swap(f.associations[0], f.associations[1]);  // "greedy" then "hopfield-sync"
  f.associations[0].name = "zeta";
  f.metrics[0].name = "zz";
  write_track_file(dir.file("f.h5"), f);
  const TrackFile back = read_track_file(dir.file("f.h5"));
  ASSERT_EQ(back.associations.size(), 2u);
  EXPECT_EQ(back.associations[0].name, "zeta");
  EXPECT_EQ(back.associations[1].name, "hopfield-sync");
  EXPECT_EQ(back.metrics[0].name, "zz");
}

// The file is readable without C++: scripts/check_h5.py opens it with h5py and asserts the schema
// (shapes, dtypes, ids, positive-definite covariances unpacked with numpy).
TEST(TrackFileLayout, ReadableWithH5pyAndFollowsTheSchema) {
  if (std::system("/usr/bin/python3 -c 'import h5py' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no python3-h5py";
  TempDir dir;
  for (StateLayout layout : {StateLayout::kXY_VXVY, StateLayout::kXYZ_VXVYVZ}) {
    write_track_file(dir.file("f.h5"), test::full_track_file(layout));
    const std::string cmd = "/usr/bin/python3 " + std::string(TRACKASSOC_SOURCE_DIR) +
                            "/scripts/check_h5.py " + dir.file("f.h5") + " --quiet >/dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  // And it fails on a file that breaks the schema.
  test::damage_file(dir.file("f.h5"), [](hid_t f) { H5Ldelete(f, "/tracks/cov", H5P_DEFAULT); });
  const std::string cmd = "/usr/bin/python3 " + std::string(TRACKASSOC_SOURCE_DIR) + "/scripts/check_h5.py " +
                          dir.file("f.h5") + " --quiet 2>/dev/null >/dev/null";
  EXPECT_NE(std::system(cmd.c_str()), 0);
}

// docs/design.md §7: the same content gives bit-identical files, whenever it is written (object
// modification times are off; HDF5 stores them with 1 s resolution, hence the pause).
TEST(TrackFileLayout, SameContentGivesBitIdenticalFiles) {
  TempDir dir;
  const TrackFile f = test::full_track_file(StateLayout::kXY_VXVY);
  write_track_file(dir.file("a.h5"), f);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  write_track_file(dir.file("b.h5"), f);
  const std::string a = test::file_bytes(dir.file("a.h5")), b = test::file_bytes(dir.file("b.h5"));
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "files differ although their content is the same";
}

// Atomic writes: a writer that fails midway (a NaN found after sensors and root attributes were
// already written to PATH.tmp) leaves the previous PATH byte-identical and no PATH.tmp behind.
TEST(TrackFileAtomic, FailedWriteLeavesTheOldFileUntouched) {
  TempDir dir;
  const std::string path = dir.file("out.h5");
  write_track_file(path, test::full_track_file(StateLayout::kXY_VXVY));
  const std::string before = test::file_bytes(path);

  TrackFile bad = test::full_track_file(StateLayout::kXY_VXVY);
  bad.measurements->bearing[4] = std::numeric_limits<double>::quiet_NaN();
  try {
    write_track_file(path, bad);
    FAIL() << "a NaN bearing was written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/measurements/bearing: row 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::file_bytes(path), before);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.h5"});
  test::expect_same_file(test::full_track_file(StateLayout::kXY_VXVY), read_track_file(path));
}

TEST(TrackFileAtomic, UnwritableDestinationIsAnInputErrorAndLeavesNothing) {
  TempDir dir;
  const TrackFile f = test::full_track_file(StateLayout::kXY_VXVY);
  EXPECT_THROW(write_track_file(dir.file("no-such-folder/out.h5"), f), InputError);
  EXPECT_THROW(write_track_file(dir.path(), f), InputError);  // a directory
  // A folder the writer cannot create files in (only meaningful when not running as root).
  if (::geteuid() != 0) {
    std::filesystem::create_directory(dir.file("ro"));
    std::filesystem::permissions(dir.file("ro"),
                                 std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    EXPECT_THROW(write_track_file(dir.file("ro/out.h5"), f), InputError);
    std::filesystem::permissions(dir.file("ro"), std::filesystem::perms::owner_all);
    EXPECT_TRUE(std::filesystem::is_empty(dir.file("ro")));
  }
  std::filesystem::remove_all(dir.file("ro"));
  EXPECT_TRUE(dir.entries().empty());
}

// The writer refuses what the reader would refuse, naming the output file, and writes nothing.
TEST(TrackFileAtomic, WriterRejectsInvalidContentAndWritesNothing) {
  TempDir dir;
  const std::string path = dir.file("out.h5");
  test::expect_writer_refuses(
      dir, path, test::full_track_file(StateLayout::kXY_VXVY),
      {
          {"/tracks/state: row 3: column 1 (y): expected a finite value, found inf",
           [](TrackFile& f) { f.tracks.state[1][3] = std::numeric_limits<double>::infinity(); }},
          {"/tracks/cov: row 2: covariance is not positive definite: diagonal element (0,0) = -1",
           [](TrackFile& f) { f.tracks.cov[0][2] = -1; }},
          {"/tracks/sensor: row 0: sensor 99 is not in /sensors/id",
           [](TrackFile& f) { f.tracks.sensor[0] = 99; }},
          {"/tracks/t: expected 24 rows", [](TrackFile& f) { f.tracks.t.pop_back(); }},
          {"/sensors/id: row 1: sensor id 10 appears twice", [](TrackFile& f) { f.sensors[1].id = 10; }},
          {"/sensors/p_detect: row 0: expected a value in [0, 1]",
           [](TrackFile& f) { f.sensors[0].p_detect = 2; }},
          {"/truth/state: row 0: expected a finite value, found nan",
           [](TrackFile& f) { f.truth->state[0][0] = std::nan(""); }},
          {"/associations/hopfield-sync/tuples: row 0: column 2 (sensor 30): expected -1 or a track number",
           [](TrackFile& f) { f.associations[0].tuples[2] = 0; }},
          {"/associations/greedy/tuples: expected 3 columns",
           [](TrackFile& f) { f.associations[1].num_sensors = 2; }},
          {"/associations: invalid name 'a/b'", [](TrackFile& f) { f.associations[0].name = "a/b"; }},
          {"/associations/greedy: name used twice", [](TrackFile& f) { f.associations[0].name = "greedy"; }},
          {"/metrics: invalid name ''", [](TrackFile& f) { f.metrics[0].name = ""; }},
      });
}

}  // namespace
}  // namespace trackassoc
