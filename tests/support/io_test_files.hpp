// Shared by the tests/io/test_io_track_file*.cpp suites: a complete TrackFile with every optional
// group, a field-by-field comparison, and helpers that damage a written file with the raw HDF5
// C API (so the reader is tested on files the writer would never produce).
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::test {

// A fresh empty folder per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ =
        std::filesystem::temp_directory_path() / ("trackassoc_io_" + std::string(info->test_suite_name()) +
                                                  "_" + info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string path() const { return path_.string(); }
  // Names of the entries in the folder (to check that no .tmp is left behind).
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(path_))
      out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::filesystem::path path_;
};

inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// A deterministic symmetric positive-definite D×D matrix: A·Aᵀ + I, with A from a small LCG.
inline Eigen::MatrixXd spd_matrix(int d, uint64_t seed) {
  Eigen::MatrixXd a(d, d);
  uint64_t s = seed * 2862933555777941757ull + 3037000493ull;
  for (int r = 0; r < d; ++r)
    for (int c = 0; c < d; ++c) {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      a(r, c) = static_cast<double>(s >> 11) / 9007199254740992.0 * 10.0 - 5.0;
    }
  // A·Aᵀ by hand: Eigen's dynamic GEMM kernel triggers a GCC 12 AVX-512 false-positive warning.
  Eigen::MatrixXd p(d, d);
  for (int r = 0; r < d; ++r)
    for (int c = 0; c < d; ++c) {
      double sum = r == c ? 1.0 : 0.0;
      for (int k = 0; k < d; ++k) sum += a(r, k) * a(c, k);
      p(r, c) = sum;
    }
  return p;
}

// A complete file: 3 sensors (ids 10, 20, 30; sensor 30 reports no tracks unless `all_sensors`),
// tracks, truth, measurements, two associations (one with an energy trace) and two metrics.
inline TrackFile full_track_file(StateLayout layout, bool all_sensors = false) {
  TrackFile f;
  f.created_by = "trackassoc test";
  f.scenario_json = R"({"name": "test"})";
  for (int s = 0; s < 3; ++s) {
    Sensor sensor;
    sensor.id = 10 * (s + 1);
    sensor.position = {125e3 + s * 1.5, -130e3 / 7.0, s * 0.25};
    sensor.sigma_range = 170 + s;
    sensor.sigma_bearing = 0.017453292519943295 / (s + 1);
    sensor.sigma_elevation = layout == StateLayout::kXY_VXVY ? 0.0 : 0.01;
    sensor.period = 1.0 + s;
    sensor.offset = 0.1 * s;
    sensor.p_detect = 0.9 + 0.05 * s;
    sensor.clutter_rate = 0.5 * s;
    sensor.reliability = 1.0 - 0.2 * s;
    f.sensors.push_back(sensor);
  }
  const int d = state_dim(layout);
  f.tracks.reset(layout);
  const int reporting = all_sensors ? 3 : 2;
  for (int s = 0; s < reporting; ++s)
    for (int trk = 0; trk < 3; ++trk)
      for (int k = 0; k < 4; ++k) {
        Eigen::VectorXd x(d);
        for (int c = 0; c < d; ++c) x[c] = 1000.0 * trk + 10.0 * c + k / 3.0 - s;
        f.tracks.push_back(10 * (s + 1), 2 - trk, 2.0 * k, x, spd_matrix(d, 100 * s + 10 * trk + k),
                           trk == 2 ? -1 : trk);
      }
  TruthTable truth(layout);
  for (int tgt = 0; tgt < 2; ++tgt)
    for (int k = 0; k < 5; ++k) {
      truth.target.push_back(tgt);
      truth.t.push_back(k * 0.5);
      for (int c = 0; c < d; ++c) truth.state[c].push_back(tgt * 1e4 + c + k * 1e-3);
    }
  f.truth = truth;
  Measurements m;
  for (int r = 0; r < 7; ++r) {
    m.sensor.push_back(10 * (1 + r % 3));
    m.t.push_back(r * 0.7);
    m.range.push_back(5e4 + r);
    m.bearing.push_back(-3.0 + r);
    if (layout == StateLayout::kXYZ_VXVYVZ) m.elevation.push_back(0.01 * r);
    m.target.push_back(r == 3 ? -1 : r % 2);
  }
  f.measurements = m;

  AssociationRecord a;
  a.name = "hopfield-sync";
  a.num_sensors = 3;
  a.tuples = {0, 2, -1, 1, 1, -1, 2, -1, -1};
  a.cost = {1.5, 2.25, 1e30};
  a.solver = "hopfield";
  a.options_json = R"({"schedule": "sync", "restarts": 8})";
  a.objective = 1e30 + 3.75;
  a.lower_bound = 3.0;
  a.gap = 0.25;
  a.runtime_s = 0.0123;
  a.seed = 18446744073709551615ull;
  a.termination = "converged";
  a.energy_rows = 2;
  a.energy_cols = 3;
  a.energy = {-1.5f, 2.f, 3.25f, 4.f, 1e-20f, -0.f};
  f.associations.push_back(a);
  AssociationRecord b;  // defaults: NaN bound and gap, no energy; zero tuples
  b.name = "greedy";
  b.num_sensors = 3;
  b.solver = "greedy";
  b.termination = "heuristic";
  f.associations.push_back(b);

  MetricsRecord m1;
  m1.name = "hopfield-sync";
  m1.correct_rate = 0.875;
  m1.false_rate = 0.125;
  m1.missed_rate = 0.0;
  m1.tables["n_targets"] = {10};
  m1.tables["per_run"] = {0.5, 0.75, 1.0};
  f.metrics.push_back(m1);
  MetricsRecord m2;
  m2.name = "empty";
  f.metrics.push_back(m2);
  return f;
}

inline void expect_same_double(double a, double b, const std::string& what) {
  if (std::isnan(a) || std::isnan(b)) {
    EXPECT_TRUE(std::isnan(a) && std::isnan(b)) << what;
  } else {
    EXPECT_EQ(a, b) << what;
  }
}

inline void expect_same_file(const TrackFile& a, const TrackFile& b) {
  EXPECT_EQ(a.created_by, b.created_by);
  EXPECT_EQ(a.scenario_json, b.scenario_json);
  EXPECT_EQ(a.sensors, b.sensors);
  EXPECT_EQ(a.tracks.layout, b.tracks.layout);
  EXPECT_EQ(a.tracks.sensor, b.tracks.sensor);
  EXPECT_EQ(a.tracks.track, b.tracks.track);
  EXPECT_EQ(a.tracks.t, b.tracks.t);
  EXPECT_EQ(a.tracks.state, b.tracks.state);
  EXPECT_EQ(a.tracks.cov, b.tracks.cov);
  EXPECT_EQ(a.tracks.truth, b.tracks.truth);
  ASSERT_EQ(a.truth.has_value(), b.truth.has_value());
  if (a.truth) {
    EXPECT_EQ(a.truth->layout, b.truth->layout);
    EXPECT_EQ(a.truth->target, b.truth->target);
    EXPECT_EQ(a.truth->t, b.truth->t);
    EXPECT_EQ(a.truth->state, b.truth->state);
  }
  ASSERT_EQ(a.measurements.has_value(), b.measurements.has_value());
  if (a.measurements) {
    EXPECT_EQ(a.measurements->sensor, b.measurements->sensor);
    EXPECT_EQ(a.measurements->t, b.measurements->t);
    EXPECT_EQ(a.measurements->range, b.measurements->range);
    EXPECT_EQ(a.measurements->bearing, b.measurements->bearing);
    EXPECT_EQ(a.measurements->elevation, b.measurements->elevation);
    EXPECT_EQ(a.measurements->target, b.measurements->target);
  }
  ASSERT_EQ(a.associations.size(), b.associations.size());
  for (std::size_t i = 0; i < a.associations.size(); ++i) {
    const auto &x = a.associations[i], &y = b.associations[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.num_sensors, y.num_sensors);
    EXPECT_EQ(x.tuples, y.tuples);
    EXPECT_EQ(x.cost, y.cost);
    EXPECT_EQ(x.solver, y.solver);
    EXPECT_EQ(x.options_json, y.options_json);
    expect_same_double(x.objective, y.objective, x.name + " objective");
    expect_same_double(x.lower_bound, y.lower_bound, x.name + " lower_bound");
    expect_same_double(x.gap, y.gap, x.name + " gap");
    EXPECT_EQ(x.runtime_s, y.runtime_s);
    EXPECT_EQ(x.seed, y.seed);
    EXPECT_EQ(x.termination, y.termination);
    EXPECT_EQ(x.energy_rows, y.energy_rows);
    EXPECT_EQ(x.energy_cols, y.energy_cols);
    ASSERT_EQ(x.energy.size(), y.energy.size());
    // Bitwise, so that -0.f and denormal-ish values are checked too.
    if (!x.energy.empty()) {
      EXPECT_EQ(0, std::memcmp(x.energy.data(), y.energy.data(), x.energy.size() * sizeof(float)));
    }
  }
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  for (std::size_t i = 0; i < a.metrics.size(); ++i) {
    EXPECT_EQ(a.metrics[i].name, b.metrics[i].name);
    EXPECT_EQ(a.metrics[i].correct_rate, b.metrics[i].correct_rate);
    EXPECT_EQ(a.metrics[i].false_rate, b.metrics[i].false_rate);
    EXPECT_EQ(a.metrics[i].missed_rate, b.metrics[i].missed_rate);
    EXPECT_EQ(a.metrics[i].tables, b.metrics[i].tables);
  }
}

// One refusal of the writer: the text its InputError must contain, and how it spoils the content.
struct SpoiledContent {
  const char* expected;
  std::function<void(TrackFile&)> spoil;
};

// For each case, a copy of `base` spoiled by it must make write_track_file(`path`) throw an
// InputError that starts with `path` and contains the expected text, leaving `dir` empty.
inline void expect_writer_refuses(const TempDir& dir, const std::string& path, const TrackFile& base,
                                  const std::vector<SpoiledContent>& cases) {
  for (const SpoiledContent& c : cases) {
    TrackFile f = base;
    c.spoil(f);
    try {
      write_track_file(path, f);
      ADD_FAILURE() << "no error for: " << c.expected;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
    EXPECT_TRUE(dir.entries().empty()) << c.expected;
  }
}

// Opens `path` read-write with the raw C API and hands the file id to `damage`.
inline void damage_file(const std::string& path, const std::function<void(hid_t)>& damage) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0) << path;
  damage(f);
  ASSERT_GE(H5Fclose(f), 0);
}

// Replaces (or creates) dataset `name` with `dims` elements of `file_type`, written from `data`
// of `mem_type`.
inline void put_dataset(hid_t f, const std::string& name, hid_t file_type, hid_t mem_type,
                        const std::vector<hsize_t>& dims, const void* data) {
  if (H5Lexists(f, name.c_str(), H5P_DEFAULT) > 0) {
    ASSERT_GE(H5Ldelete(f, name.c_str(), H5P_DEFAULT), 0);
  }
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t set = H5Dcreate2(f, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(set, 0) << name;
  ASSERT_GE(H5Dwrite(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0);
  H5Dclose(set);
  H5Sclose(space);
}

inline std::vector<double> read_all_doubles(hid_t f, const std::string& name) {
  const hid_t set = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  std::vector<double> v(H5Sget_simple_extent_npoints(space));
  H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(set);
  return v;
}

// Sets attribute `name` of object `object` to a fixed-length string (a writer other than ours).
inline void put_string_attribute(hid_t f, const std::string& object, const std::string& name,
                                 const std::string& value) {
  if (H5Aexists_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr =
      H5Acreate_by_name(f, object.c_str(), name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(attr, 0);
  H5Awrite(attr, type, value.c_str());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

// A variable-length UTF-8 string attribute, as h5py writes a Python str.
inline void put_vlen_string_attribute(hid_t f, const std::string& object, const std::string& name,
                                      const std::string& value) {
  if (H5Aexists_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr =
      H5Acreate_by_name(f, object.c_str(), name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(attr, 0);
  const char* p = value.c_str();
  H5Awrite(attr, type, &p);
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

inline void put_int_attribute(hid_t f, const std::string& object, const std::string& name, int64_t value) {
  if (H5Aexists_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate_by_name(f, object.c_str(), name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT,
                                       H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(attr, 0);
  H5Awrite(attr, H5T_NATIVE_INT64, &value);
  H5Aclose(attr);
  H5Sclose(space);
}

// The InputError message of read_track_file(path), or "no error".
inline std::string read_error(const std::string& path) {
  try {
    read_track_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace trackassoc::test
