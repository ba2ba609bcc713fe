// Siamese model files: round trip, and clear errors for corrupted or wrong files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "io/hdf5_wrapper.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"

using namespace trackassoc;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("trackassoc_siamese_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Removes temp_dir() when the test program ends.
class RemoveTempDir : public ::testing::Environment {
 public:
  void TearDown() override { fs::remove_all(temp_dir()); }
};
::testing::Environment* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

SiameseModel<float> model_for_test() {
  SiameseModel<float> m;
  m.shape.hidden = 5;
  m.shape.fc = 7;
  m.normalisation.position_scale = 12345.0;
  m.normalisation.t0 = 2.5;
  siamese_initialise(m, 99);
  return m;
}

std::string error_of(const std::string& path) {
  try {
    read_siamese_model(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Writes a model, then lets `edit` rewrite one dataset or attribute through a fresh file copy.
std::string write_valid(const std::string& name) {
  const std::string path = (temp_dir() / name).string();
  write_siamese_model(path, model_for_test(), R"({"note":"test"})");
  return path;
}

}  // namespace

TEST(SiameseModelFile, RoundTripIsBitIdentical) {
  const SiameseModel<float> m = model_for_test();
  const std::string path = write_valid("roundtrip.h5");
  const LoadedSiameseModel loaded = read_siamese_model(path);
  EXPECT_EQ(loaded.model.shape.hidden, 5);
  EXPECT_EQ(loaded.model.shape.fc, 7);
  EXPECT_EQ(loaded.model.normalisation.position_scale, 12345.0);
  EXPECT_EQ(loaded.model.normalisation.t0, 2.5);
  EXPECT_EQ(loaded.training_json, R"({"note":"test"})");
  ASSERT_EQ(loaded.model.params.size(), m.params.size());
  for (std::size_t k = 0; k < m.params.size(); ++k) ASSERT_EQ(loaded.model.params[k], m.params[k]) << k;
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(SiameseModelFile, ConcatenatedLstmBaselineRoundTrips) {
  SiameseModel<float> m;
  m.shape.architecture = PairArchitecture::kConcatLstm;
  m.shape.hidden = 3;
  m.shape.fc = 4;
  siamese_initialise(m, 7);
  const std::string path = (temp_dir() / "lstm.h5").string();
  write_siamese_model(path, m);
  const LoadedSiameseModel back = read_siamese_model(path);
  EXPECT_EQ(back.model.shape.architecture, PairArchitecture::kConcatLstm);
  ASSERT_EQ(back.model.params.size(), m.params.size());
  for (std::size_t k = 0; k < m.params.size(); ++k) ASSERT_EQ(back.model.params[k], m.params[k]);
  const h5::File f = h5::File::open_read_only(path);
  EXPECT_TRUE(f.root().open_group("branch").has("forward"));
  EXPECT_FALSE(f.root().open_group("branch").has("backward"));
}

TEST(SiameseModelFile, WeightsAreStoredRowMajorInPyTorchOrientation) {
  // Element (r, c) of Wx is params[c·4H + r] in memory; the file holds it at [r][c].
  const SiameseModel<float> m = model_for_test();
  const std::string path = write_valid("layout.h5");
  const h5::File f = h5::File::open_read_only(path);
  std::vector<hsize_t> dims;
  const auto wx = f.root().open_group("branch").open_group("forward").read_floats("Wx", 2, dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{20, 3}));
  EXPECT_EQ(wx[2 * 3 + 1], m.params[1 * 20 + 2]);
  const auto b2 = f.root().open_group("head").read_floats("b2", 1, dims);
  EXPECT_EQ(b2[0], m.params.back());
}

TEST(SiameseModelFile, RandomBytesGiveAClearError) {
  const std::string path = (temp_dir() / "random.h5").string();
  std::ofstream out(path, std::ios::binary);
  CounterRng rng(5);
  for (int k = 0; k < 4096; ++k) out.put(static_cast<char>(rng.next_u64() & 0xff));
  out.close();
  EXPECT_NE(error_of(path).find("not an HDF5 file"), std::string::npos) << error_of(path);
}

TEST(SiameseModelFile, TruncatedFileGivesAClearError) {
  const std::string path = write_valid("truncated.h5");
  fs::resize_file(path, fs::file_size(path) / 2);
  const std::string e = error_of(path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_FALSE(e.empty());
}

TEST(SiameseModelFile, EmptyAndMissingFiles) {
  const std::string empty = (temp_dir() / "empty.h5").string();
  std::ofstream(empty).close();
  EXPECT_NE(error_of(empty).find("empty file"), std::string::npos) << error_of(empty);
  EXPECT_NE(error_of((temp_dir() / "nope.h5").string()).find("does not exist"), std::string::npos);
}

TEST(SiameseModelFile, MissingDatasetWrongShapeNaNAndWrongFormat) {
  const SiameseModel<float> m = model_for_test();
  // A model file written by hand through io/hdf5_wrapper.hpp; `tweak` adds /head/b2 (or not).
  auto make = [&](const std::string& name, auto&& tweak) {
    const std::string path = (temp_dir() / name).string();
    h5::File f = h5::File::create(path);
    const h5::Group root = f.root();
    root.write_attribute("format", std::string("trackassoc-siamese-model"));
    root.write_attribute("schema_version", int32_t{1});
    root.write_attribute("input", int32_t{3});
    root.write_attribute("hidden", int32_t{5});
    root.write_attribute("fc", int32_t{7});
    root.write_attribute("architecture", std::string("siamese"));
    for (const char* a : {"x0", "y0", "position_scale", "t0", "time_scale"}) root.write_attribute(a, 1.0);
    root.write_attribute("training", std::string("{}"));
    std::vector<float> zeros(1000, 0.0f);
    auto part = [&](std::size_t n) { return std::span<const float>(zeros.data(), n); };
    const h5::Group branch = root.create_group("branch");
    for (const char* d : {"forward", "backward"}) {
      const h5::Group g = branch.create_group(d);
      g.write_dataset("Wx", part(60), {20, 3});
      g.write_dataset("Wh", part(100), {20, 5});
      g.write_dataset("b", part(20), {20});
    }
    const h5::Group head = root.create_group("head");
    head.write_dataset("W1", part(70), {7, 10});
    head.write_dataset("b1", part(7), {7});
    head.write_dataset("w2", part(7), {7});
    tweak(head, zeros);
    f.close();
    return path;
  };
  // Valid as built plus b2: loads.
  EXPECT_EQ(error_of(make("ok.h5",
                          [](const h5::Group& g, std::vector<float>& z) {
                            g.write_dataset("b2", std::span<const float>(z.data(), 1), {1});
                          })),
            "");
  // Missing /head/b2.
  const std::string e1 = error_of(make("missing.h5", [](const h5::Group&, std::vector<float>&) {}));
  EXPECT_NE(e1.find("/head/b2"), std::string::npos) << e1;
  EXPECT_NE(e1.find("missing"), std::string::npos) << e1;
  // Wrong shape.
  const std::string e2 = error_of(make("shape.h5", [](const h5::Group& g, std::vector<float>& z) {
    g.write_dataset("b2", std::span<const float>(z.data(), 2), {2});
  }));
  EXPECT_NE(e2.find("/head/b2: has shape 2, expected 1"), std::string::npos) << e2;
  // NaN.
  const std::string e3 = error_of(make("nan.h5", [](const h5::Group& g, std::vector<float>& z) {
    z[0] = std::numeric_limits<float>::quiet_NaN();
    g.write_dataset("b2", std::span<const float>(z.data(), 1), {1});
  }));
  EXPECT_NE(e3.find("/head/b2: has a non-finite value"), std::string::npos) << e3;
  // Integers where floats belong are converted, as every reader of io/hdf5_wrapper.hpp does; a
  // non-numeric dtype is refused.
  EXPECT_EQ(error_of(make("int.h5",
                          [](const h5::Group& g, std::vector<float>&) {
                            const int32_t one = 1;
                            g.write_dataset("b2", std::span<const int32_t>(&one, 1), {1});
                          })),
            "");
  const std::string e4 = error_of(make("dtype.h5", [](const h5::Group& g, std::vector<float>&) {
    const hsize_t one = 1;
    h5::Handle space(H5Screate_simple(1, &one, nullptr), H5Sclose);
    h5::Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type.get(), 4);
    h5::Handle set(H5Dcreate2(g.id(), "b2", type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose);
    ASSERT_TRUE(set.valid());
    ASSERT_GE(H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, "abc"), 0);
  }));
  EXPECT_NE(e4.find("/head/b2: expected numeric"), std::string::npos) << e4;
  // A different kind of HDF5 file.
  const std::string path = (temp_dir() / "other.h5").string();
  {
    h5::File f = h5::File::create(path);
    f.root().write_attribute("format", std::string("trackassoc"));
    f.close();
  }
  EXPECT_NE(error_of(path).find("expected 'trackassoc-siamese-model'"), std::string::npos) << error_of(path);
  // An HDF5 file without the format attribute.
  const std::string bare = (temp_dir() / "bare.h5").string();
  h5::File::create(bare).close();
  EXPECT_NE(error_of(bare).find("not a Siamese model file (the root has no 'format' attribute"),
            std::string::npos)
      << error_of(bare);
}

TEST(SiameseModelFile, FailedWriteLeavesTheOldFileIntact) {
  const std::string path = write_valid("keep.h5");
  const auto before = fs::file_size(path);
  SiameseModel<float> bad = model_for_test();
  bad.params.pop_back();
  EXPECT_THROW(write_siamese_model(path, bad), InputError);
  EXPECT_EQ(fs::file_size(path), before);
  EXPECT_EQ(error_of(path), "");
}
