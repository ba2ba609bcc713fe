// export csv --what associations|unassociated|registration (engine/pipeline/result_tables.hpp) on a
// small file whose tables are written out by hand below, so the C++-only builds (the sanitizer
// build runs no Python) check them too; tests/python/test_export_csv.py checks the CLI on
// simulated files and the pandas round trip.
#include <gtest/gtest.h>

#include <sstream>

#include "engine/pipeline/result_tables.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

// full_track_file: sensors 10, 20, 30, each tracks 2, 1, 0 (in that row order) reporting at t = 0,
// 2, 4, 6; row r of sensor column s and track k is r = (3s + 2 - k)·4 + report.
TrackFile file_with_association() {
  TrackFile f = test::full_track_file(StateLayout::kXY_VXVY, true);
  f.associations.clear();
  f.metrics.clear();
  f.fused.clear();
  f.system_tracks.clear();
  AssociationRecord a;
  a.name = "mine";
  a.num_sensors = 3;
  a.tuples = {0, 0, 0, /**/ 1, 1, -1, /**/ -1, -1, 1, /**/ 2, -1, -1};
  a.target = {0, 1, 1, 2};  // target 1: tuples 1 and 2 (a segment on sensor 30)
  a.cost = {0.5, 1.25, -3.0, 0.0};
  a.solver = "test";
  f.associations.push_back(a);
  return f;
}

std::string table(const std::string& path, const TrackFile& f, ResultTable what) {
  std::ostringstream out;
  export_result_table(path, f, what, "", out);
  return out.str();
}

TEST(ResultTables, AssociationsAndUnassociatedWithSourceTrack) {
  TempDir dir;
  const std::string path = dir.file("a.h5");
  const TrackFile f = file_with_association();
  write_track_file(path, f);
  // without /tracks/source_track the source is the track itself
  EXPECT_EQ(table(path, f, ResultTable::kAssociations),
            "target,tuple,sensor,track,source_track,cost\n"
            "0,0,10,0,0,0.5\n0,0,20,0,0,0.5\n0,0,30,0,0,0.5\n"
            "1,1,10,1,1,1.25\n1,1,20,1,1,1.25\n1,2,30,1,1,-3\n2,3,10,2,2,0\n");
  // /tracks/source_track = 7r + 1: a track's source is that of its first report (row (3s + 2 - k)·4)
  test::damage_file(path, [&](hid_t h) {
    std::vector<int32_t> source(f.tracks.size());
    for (std::size_t r = 0; r < source.size(); ++r) source[r] = static_cast<int32_t>(7 * r + 1);
    test::put_dataset(h, "/tracks/source_track", H5T_STD_I32LE, H5T_NATIVE_INT32, {source.size()},
                      source.data());
  });
  EXPECT_EQ(table(path, f, ResultTable::kAssociations),
            "target,tuple,sensor,track,source_track,cost\n"
            "0,0,10,0,57,0.5\n0,0,20,0,141,0.5\n0,0,30,0,225,0.5\n"
            "1,1,10,1,29,1.25\n1,1,20,1,113,1.25\n1,2,30,1,197,-3\n2,3,10,2,1,0\n");
  // Unassociated: track 2 of every sensor (alone in tuple 3, or in none); track 1 of sensor 30 is
  // alone in its tuple but its target has two other tracks.
  EXPECT_EQ(table(path, f, ResultTable::kUnassociated),
            "sensor,track,source_track,first_t,last_t,reports\n"
            "10,2,1,0,6,4\n20,2,85,0,6,4\n30,2,169,0,6,4\n");
}

TEST(ResultTables, RegistrationOneRowPerSensor) {
  TempDir dir;
  const std::string path = dir.file("r.h5");
  const TrackFile f = file_with_association();
  write_track_file(path, f);
  EXPECT_THROW(
      {
        try {
          table(path, f, ResultTable::kRegistration);
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("no /registration group"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
  test::damage_file(path, [&](hid_t h) {
    H5Gclose(H5Gcreate2(h, "/registration", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    const double bias[] = {0.5, -1.0, 2.0};
    const double offset[] = {1, 2, 3, 4, 5, 6};
    const double junk[] = {9, 9, 9, 9, 9};
    test::put_dataset(h, "/registration/bias", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {3}, bias);
    test::put_dataset(h, "/registration/offset", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {3, 2}, offset);
    test::put_dataset(h, "/registration/junk", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {5}, junk);
  });
  std::ostringstream out;
  const ResultTableSummary s = export_result_table(path, f, ResultTable::kRegistration, "", out);
  EXPECT_EQ(out.str(), "sensor,bias,offset_0,offset_1\n10,0.5,1,2\n20,-1,3,4\n30,2,5,6\n");
  ASSERT_EQ(s.skipped.size(), 1u);
  EXPECT_NE(s.skipped[0].find("junk"), std::string::npos);
  // /registration/sensor (written by associate) labels the rows, in its own order, and is not a
  // second "sensor" column (was: "sensor,...,sensor" with the /sensors ids beside).
  test::damage_file(path, [&](hid_t h) {
    const int32_t ids[] = {30, 10, 20};
    test::put_dataset(h, "/registration/sensor", H5T_STD_I32LE, H5T_NATIVE_INT32, {3}, ids);
  });
  std::ostringstream labelled;
  export_result_table(path, f, ResultTable::kRegistration, "", labelled);
  EXPECT_EQ(labelled.str(), "sensor,bias,offset_0,offset_1\n30,0.5,1,2\n10,-1,3,4\n20,2,5,6\n");
}

TEST(ResultTables, NamePicksTheGroup) {
  TempDir dir;
  const std::string path = dir.file("n.h5");
  TrackFile f = file_with_association();
  AssociationRecord b = f.associations.front();
  b.name = "other";
  b.cost = {1, 2, 3, 4};
  f.associations.push_back(b);
  write_track_file(path, f);
  std::ostringstream out;
  EXPECT_THROW(export_result_table(path, f, ResultTable::kAssociations, "", out),
               InputError);  // two: name one
  EXPECT_THROW(export_result_table(path, f, ResultTable::kAssociations, "nosuch", out), InputError);
  export_result_table(path, f, ResultTable::kAssociations, "other", out);
  EXPECT_NE(out.str().find("1,2,30,1,1,3\n"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace trackassoc
