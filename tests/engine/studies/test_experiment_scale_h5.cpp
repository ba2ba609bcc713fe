// `experiment scale` writes its table as HDF5 (engine/studies/scale/experiment_scale.hpp, write_scale_h5):
// rows written and read back value by value (with a failed size and a size without the dense path), the CLI's
// scale.h5 at a tiny size, and scripts/plot_scale.py drawing from it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "engine/studies/scale/experiment_scale.hpp"
#include "io/hdf5_wrapper.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;

ScaleRow make_row(int32_t n, bool dense, bool identical) {
  ScaleRow r;
  r.n = n;
  r.tracks = {n, n - 1, n - 2};
  r.candidate_pairs = 3 * n + 7;
  r.gated_pairs = 3 * n;
  r.components = n - 3;
  r.largest_component = 4;
  // Stages out of the table's order, and "components" missing: the columns go by name.
  r.stage = {"candidates", "alignment", "statistics", "solve"};
  r.stage_s = {0.25, 0.5, 0.125, 0.0625};
  r.stage_peak_mib = {11, 10, 12, 13};
  r.stage_data_mib = {1.5, 2.5, 3.5, 4.5};
  r.total_s = 0.9375;
  r.peak_mib = 13;
  r.correct_rate = 0.98, r.false_rate = 0.015, r.missed_rate = 0.005;
  r.dense_run = dense;
  r.dense_total_s = 2.5, r.dense_peak_mib = 40, r.dense_correct_rate = 0.97;
  r.dense_identical = identical;
  r.dense_gated_pairs = 3 * n;
  return r;
}

TEST(ExperimentScaleH5, RowsReadBackExactly) {
  std::vector<ScaleRow> rows{make_row(100, true, true), make_row(300, true, false),
                             make_row(1000, false, false)};
  ScaleRow failed;
  failed.n = 30000;
  failed.error = "out of memory, \"quoted\"";
  rows.push_back(failed);
  const std::string path = ::testing::TempDir() + "/trackassoc_scale_rows.h5";
  const nlohmann::json options = {{"solver", "pairwise"}, {"sizes", {100, 300, 1000, 30000}}};
  write_scale_h5(path, rows, options, 0.92);
  ASSERT_FALSE(std::filesystem::exists(path + ".tmp"));

  const h5::File f = h5::File::open_read_only(path);
  const h5::Group root = f.root();
  EXPECT_EQ(root.read_string_attribute("format"), "trackassoc-experiment");
  EXPECT_EQ(root.read_string_attribute("experiment"), "scale");
  EXPECT_EQ(nlohmann::json::parse(root.read_string_attribute("options")), options);
  EXPECT_DOUBLE_EQ(root.read_double_attribute("loglog_slope_n_ge_1000"), 0.92);
  const h5::Group g = root.open_group("scale");
  std::vector<hsize_t> dims;
  auto ints = [&](const char* name, int rank = 1) { return g.read_integers(name, rank, dims); };
  auto doubles = [&](const char* name, int rank = 1) { return g.read_doubles(name, rank, dims); };

  EXPECT_EQ(ints("n"), (std::vector<int64_t>{100, 300, 1000, 30000}));
  EXPECT_EQ(ints("tracks", 2), (std::vector<int64_t>{100, 99, 98, 300, 299, 298, 1000, 999, 998, 0, 0, 0}));
  EXPECT_EQ(dims, (std::vector<hsize_t>{4, 3}));
  EXPECT_EQ(ints("components"), (std::vector<int64_t>{97, 297, 997, 0}));
  EXPECT_EQ(ints("ok"), (std::vector<int64_t>{1, 1, 1, 0}));
  EXPECT_EQ(ints("dense_run"), (std::vector<int64_t>{1, 1, 0, 0}));
  EXPECT_EQ(ints("dense_identical"), (std::vector<int64_t>{1, 0, -1, -1}));
  const auto cand = doubles("candidate_pairs");
  EXPECT_EQ(cand[0], 307.0);
  EXPECT_EQ(cand[2], 3007.0);
  EXPECT_TRUE(std::isnan(cand[3]));
  // Stage columns in the attribute's order: alignment, candidates, statistics, components, solve.
  EXPECT_EQ(g.read_string_attribute("stages"), "alignment,candidates,statistics,components,solve");
  const auto st = doubles("stage_s", 2);
  ASSERT_EQ(dims, (std::vector<hsize_t>{4, 5}));
  EXPECT_EQ(st[0], 0.5);
  EXPECT_EQ(st[1], 0.25);
  EXPECT_EQ(st[2], 0.125);
  EXPECT_TRUE(std::isnan(st[3]));  // no components stage in this row
  EXPECT_EQ(st[4], 0.0625);
  for (int q = 0; q < 5; ++q) EXPECT_TRUE(std::isnan(st[15 + q]));  // the failed size
  const auto data = doubles("stage_data_mib", 2);
  EXPECT_EQ(data[0], 2.5);
  EXPECT_EQ(data[1], 1.5);
  EXPECT_EQ(doubles("total_s")[1], 0.9375);
  EXPECT_EQ(doubles("correct_rate")[0], 0.98);
  EXPECT_EQ(doubles("missed_rate")[2], 0.005);
  const auto dense_total = doubles("dense_total_s");
  EXPECT_EQ(dense_total[0], 2.5);
  EXPECT_TRUE(std::isnan(dense_total[2]));
  const auto errors = nlohmann::json::parse(g.read_string_attribute("errors"));
  EXPECT_EQ(errors, (nlohmann::json{"", "", "", "out of memory, \"quoted\""}));
  std::filesystem::remove(path);
}

class ExperimentScaleH5Cli : public CliFixture {};

TEST_F(ExperimentScaleH5Cli, WritesScaleH5AndPlotsFromIt) {
  const std::string out = path("scale");
  const auto r = run("experiment scale --sizes 60 --dense-max 60 --no-plots --threads 1 --output " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  const h5::File f = h5::File::open_read_only(out + "/scale.h5");
  const h5::Group g = f.root().open_group("scale");
  std::vector<hsize_t> dims;
  EXPECT_EQ(g.read_integers("n", 1, dims), (std::vector<int64_t>{60}));
  EXPECT_EQ(g.read_integers("ok", 1, dims), (std::vector<int64_t>{1}));
  EXPECT_EQ(g.read_integers("dense_identical", 1, dims), (std::vector<int64_t>{1}));
  const auto tracks = g.read_integers("tracks", 2, dims);
  EXPECT_EQ(tracks, (std::vector<int64_t>{60, 60, 60}));
  const double correct = g.read_doubles("correct_rate", 1, dims)[0];
  EXPECT_GT(correct, 0.9);
  EXPECT_LE(correct, 1.0);
  const auto st = g.read_doubles("stage_s", 2, dims);
  double sum = 0;
  for (double s : st) sum += s;
  EXPECT_LE(sum, g.read_doubles("total_s", 1, dims)[0] * (1 + 1e-9));
  // The plot script reads the HDF5 file (Debian python3 with h5py + matplotlib).
  if (std::system("/usr/bin/python3 -c 'import h5py, matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with h5py and matplotlib not available";
  const std::string png = path("scale.png");
  const std::string cmd = "/usr/bin/python3 " + std::string(TRACKASSOC_SOURCE_DIR) +
                          "/scripts/plot_scale.py " + out + "/scale.h5 " + png;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
}

}  // namespace
}  // namespace trackassoc
