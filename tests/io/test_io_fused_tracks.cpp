// /fused/<name> groups (io/fused_tracks_file.hpp): exact round trips, kept across a
// read-modify-write, the datasets as h5py sees them, and a clear error for every kind of bad
// content, from the writer (nothing written) and from the reader (a file damaged by another writer).
#include <hdf5.h>

#include "io/hdf5_wrapper.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

// Two fused rows of tuple 0 and one of tuple 1 of the full file's association "hopfield-sync".
FusedTrackRecord fused_record(StateLayout layout, const std::string& rule) {
  FusedTrackRecord r;
  r.name = "hopfield-sync-" + rule;
  r.association = "hopfield-sync";
  r.rule = rule;
  r.ci_criterion = rule == "ci" ? "det" : "";
  r.cross_covariance = rule == "bsc" ? "common-process-noise" : "none";
  r.options_json = R"({"rule": ")" + rule + "\"}";
  r.layout = layout;
  r.num_sensors = 3;
  r.tuples = {0, 2, -1, 1, 1, -1, 2, -1, -1};
  r.tuple = {0, 0, 1};
  r.t = {0.5, 2.0, 1.25};
  r.sources = {2, 2, 2};
  r.truth = {0, 0, -1};
  const int d = state_dim(layout), p = packed_size(d);
  r.state.assign(d, {});
  r.cov.assign(p, {});
  for (int i = 0; i < 3; ++i) {
    const Eigen::MatrixXd P = test::spd_matrix(d, 7 + i);
    for (int c = 0; c < d; ++c) r.state[c].push_back(100.0 * i + c + 0.125);
    for (int a = 0, k = 0; a < d; ++a)
      for (int b = a; b < d; ++b, ++k) r.cov[k].push_back(P(a, b));
  }
  if (rule == "ci") r.omega = {0.25, 0.75, 0.0, 1.0 / 3, 2.0 / 3, 0.0, 0.5, 0.5, 0.0};
  return r;
}

TrackFile file_with_fused(StateLayout layout) {
  TrackFile f = test::full_track_file(layout, /*all_sensors=*/true);
  f.fused.push_back(fused_record(layout, "ci"));
  f.fused.push_back(fused_record(layout, "bsc"));
  f.fused.back().position_rmse = 12.5;
  f.fused.back().position_rmse_rows = 2;
  f.fused.back().sensor_position_rmse = {20.25, std::nan(""), 31.0};
  f.fused.back().sensor_position_rmse_rows = {2, 0, 1};
  return f;
}

void expect_same_fused(const FusedTrackRecord& a, const FusedTrackRecord& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.association, b.association);
  EXPECT_EQ(a.rule, b.rule);
  EXPECT_EQ(a.ci_criterion, b.ci_criterion);
  EXPECT_EQ(a.cross_covariance, b.cross_covariance);
  EXPECT_EQ(a.options_json, b.options_json);
  EXPECT_EQ(a.layout, b.layout);
  EXPECT_EQ(a.num_sensors, b.num_sensors);
  EXPECT_EQ(a.tuples, b.tuples);
  EXPECT_EQ(a.tuple, b.tuple);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.state, b.state);
  EXPECT_EQ(a.cov, b.cov);
  EXPECT_EQ(a.sources, b.sources);
  EXPECT_EQ(a.truth, b.truth);
  EXPECT_EQ(a.omega, b.omega);
  test::expect_same_double(a.position_rmse, b.position_rmse, a.name + " position_rmse");
  EXPECT_EQ(a.position_rmse_rows, b.position_rmse_rows);
  ASSERT_EQ(a.sensor_position_rmse.size(), b.sensor_position_rmse.size());
  for (std::size_t s = 0; s < a.sensor_position_rmse.size(); ++s)
    test::expect_same_double(a.sensor_position_rmse[s], b.sensor_position_rmse[s], a.name + " sensor rmse");
  EXPECT_EQ(a.sensor_position_rmse_rows, b.sensor_position_rmse_rows);
}

class FusedRoundTrip : public ::testing::TestWithParam<StateLayout> {};

TEST_P(FusedRoundTrip, EveryValueComesBackAndSurvivesReadModifyWrite) {
  TempDir dir;
  const TrackFile f = file_with_fused(GetParam());
  write_track_file(dir.file("a.h5"), f);
  TrackFile back = read_track_file(dir.file("a.h5"));
  test::expect_same_file(f, back);
  ASSERT_EQ(back.fused.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) expect_same_fused(f.fused[i], back.fused[i]);
  // A command that changes something else (here a metric) keeps /fused as it was.
  back.metrics.pop_back();
  write_track_file(dir.file("b.h5"), back);
  const TrackFile again = read_track_file(dir.file("b.h5"));
  ASSERT_EQ(again.fused.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) expect_same_fused(f.fused[i], again.fused[i]);
}

INSTANTIATE_TEST_SUITE_P(Layouts, FusedRoundTrip,
                         ::testing::Values(StateLayout::kXY_VXVY, StateLayout::kXYZ_VXVYVZ));

TEST(FusedLayout, DatasetsHaveTheSchemaShapes) {
  TempDir dir;
  write_track_file(dir.file("a.h5"), file_with_fused(StateLayout::kXY_VXVY));
  h5::File h = h5::File::open_read_only(dir.file("a.h5"));
  const h5::Group g = h.root().open_group("fused").open_group("hopfield-sync-ci");
  EXPECT_EQ(g.dataset_shape("tuples"), (std::vector<hsize_t>{3, 3}));
  EXPECT_EQ(g.dataset_shape("tuple"), (std::vector<hsize_t>{3}));
  EXPECT_EQ(g.dataset_shape("state"), (std::vector<hsize_t>{3, 4}));
  EXPECT_EQ(g.dataset_shape("cov"), (std::vector<hsize_t>{3, 10}));
  EXPECT_EQ(g.dataset_shape("omega"), (std::vector<hsize_t>{3, 3}));
  EXPECT_EQ(g.read_string_attribute("rule"), "ci");
  EXPECT_EQ(g.read_string_attribute("ci_criterion"), "det");
  EXPECT_EQ(g.read_string_attribute("association"), "hopfield-sync");
  EXPECT_FALSE(g.has("sensor_position_rmse"));
  const h5::Group b = h.root().open_group("fused").open_group("hopfield-sync-bsc");
  EXPECT_FALSE(b.has("omega"));
  EXPECT_EQ(b.read_double_attribute("position_rmse"), 12.5);
  EXPECT_EQ(b.dataset_shape("sensor_position_rmse"), (std::vector<hsize_t>{3}));
}

TEST(FusedErrors, WriterRefusesBadContentAndWritesNothing) {
  TempDir dir;
  const std::string path = dir.file("out.h5");
  test::expect_writer_refuses(
      dir, path, file_with_fused(StateLayout::kXY_VXVY),
      {
          {"/fused/hopfield-sync-ci attribute association: \"gone\" is not an /associations group",
           [](TrackFile& f) { f.fused[0].association = "gone"; }},
          {"/fused/hopfield-sync-ci/tuples: differ from /associations/hopfield-sync/tuples",
           [](TrackFile& f) { f.associations[0].tuples[0] = 1, f.associations[0].tuples[3] = 0; }},
          {"/fused/hopfield-sync-ci attribute rule: expected \"naive\", \"bsc\" or \"ci\", found \"mean\"",
           [](TrackFile& f) { f.fused[0].rule = "mean"; }},
          {"/fused/hopfield-sync-ci/tuple: row 2: expected a row of tuples in [0, 3), found 3",
           [](TrackFile& f) { f.fused[0].tuple[2] = 3; }},
          {"/fused/hopfield-sync-ci/t: row 1: times must increase strictly within a tuple",
           [](TrackFile& f) { f.fused[0].t[1] = 0.5; }},
          {"/fused/hopfield-sync-ci/sources: row 0: expected 2..3, found 1",
           [](TrackFile& f) { f.fused[0].sources[0] = 1; }},
          {"/fused/hopfield-sync-ci/cov: row 1: not positive definite",
           [](TrackFile& f) { f.fused[0].cov[0][1] = -1; }},
          {"/fused/hopfield-sync-ci/omega: row 0: weights sum to",
           [](TrackFile& f) { f.fused[0].omega[0] = 0.5; }},
          {"/fused/hopfield-sync-ci: row 2: t and state must be finite",
           [](TrackFile& f) { f.fused[0].state[1][2] = std::nan(""); }},
          {"/fused/hopfield-sync-bsc/omega: present without rule ci",
           [](TrackFile& f) {
             f.fused[1].omega = {1, 0, 0};
           }},
          {"/fused/hopfield-sync-ci: name used twice",
           [](TrackFile& f) { f.fused[1].name = f.fused[0].name; }},
          {"/fused: invalid name 'a/b'", [](TrackFile& f) { f.fused[0].name = "a/b"; }},
          {"/fused/hopfield-sync-ci attribute state_layout: expected \"x,y,vx,vy\" (as /tracks)",
           [](TrackFile& f) { f.fused[0].layout = StateLayout::kXYZ_VXVYVZ; }},
      });
}

TEST(FusedErrors, ReaderNamesTheDamagedDataset) {
  TempDir dir;
  const std::string path = dir.file("a.h5");
  struct Case {
    const char* expected;
    std::function<void(hid_t)> damage;
  };
  const Case cases[] = {
      {"/fused/hopfield-sync-ci/sources: expected 3 rows",
       [](hid_t f) {
         const int32_t v[] = {2, 2};
         test::put_dataset(f, "/fused/hopfield-sync-ci/sources", H5T_STD_I32LE, H5T_NATIVE_INT32, {2}, v);
       }},
      {"/fused/hopfield-sync-ci/state: expected shape 3x4",
       [](hid_t f) {
         const double v[6] = {};
         test::put_dataset(f, "/fused/hopfield-sync-ci/state", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {3, 2}, v);
       }},
      {"/fused/hopfield-sync-ci/tuples: differ from /associations/hopfield-sync/tuples",
       [](hid_t f) {
         const int32_t v[9] = {1, 2, -1, 0, 1, -1, 2, -1, -1};
         test::put_dataset(f, "/fused/hopfield-sync-ci/tuples", H5T_STD_I32LE, H5T_NATIVE_INT32, {3, 3}, v);
       }},
      {"/fused/hopfield-sync-bsc/sources: row 1: expected 2..3, found 7",
       [](hid_t f) {
         const int32_t v[] = {2, 7, 2};
         test::put_dataset(f, "/fused/hopfield-sync-bsc/sources", H5T_STD_I32LE, H5T_NATIVE_INT32, {3}, v);
       }},
      {"/fused/hopfield-sync-ci/rule: missing attribute",
       [](hid_t f) { H5Adelete_by_name(f, "/fused/hopfield-sync-ci", "rule", H5P_DEFAULT); }},
  };
  for (const Case& c : cases) {
    write_track_file(path, file_with_fused(StateLayout::kXY_VXVY));
    test::damage_file(path, c.damage);
    const std::string err = test::read_error(path);
    EXPECT_NE(err.find(c.expected), std::string::npos) << "expected '" << c.expected << "', got: " << err;
    EXPECT_NE(err.find(path), std::string::npos) << err;
  }
}

}  // namespace
}  // namespace trackassoc
