// Siamese model files (see siamese_model_file.hpp).
#include "io/siamese_model_file.hpp"

#include <cmath>

#include "io/atomic_file.hpp"
#include "io/siamese_hdf5.hpp"
#include "kernels/error.hpp"

namespace trackassoc {
namespace {

constexpr const char* kFormat = "trackassoc-siamese-model";
constexpr int64_t kSchemaVersion = 1;

// A parameter block of the flat vector: column-major rows×cols in memory, row-major in the file.
struct Block {
  std::string name;
  int64_t offset, rows, cols;  // cols == 0: a vector
};

std::vector<Block> blocks(const SiameseShape& s) {
  const int64_t H = s.hidden, F = s.input, per_dir = s.lstm().parameter_count();
  std::vector<Block> out;
  const char* dirs[2] = {"/branch/forward/", "/branch/backward/"};
  for (int d = 0; d < s.directions(); ++d) {
    const int64_t o = d * per_dir;
    out.push_back({std::string(dirs[d]) + "Wx", o, 4 * H, F});
    out.push_back({std::string(dirs[d]) + "Wh", o + 4 * H * F, 4 * H, H});
    out.push_back({std::string(dirs[d]) + "b", o + 4 * H * F + 4 * H * H, 4 * H, 0});
  }
  const int64_t h = s.branch_parameter_count(), fc = s.fc, e = s.embedding();
  out.push_back({"/head/W1", h, fc, e});
  out.push_back({"/head/b1", h + fc * e, fc, 0});
  out.push_back({"/head/w2", h + fc * e + fc, fc, 0});
  out.push_back({"/head/b2", h + fc * e + 2 * fc, 1, 0});
  return out;
}

}  // namespace

void write_siamese_model(const std::string& path, const SiameseModel<float>& model,
                         const std::string& training_json) {
  model.shape.validate();
  model.normalisation.validate();
  require(static_cast<int64_t>(model.params.size()) == model.shape.parameter_count(), "model",
          "parameter vector size does not match its shape");
  write_atomically(path, [&](const std::string& tmp) {
    siamese_h5::File f = siamese_h5::File::create(tmp);
    f.write_attribute("/", "format", std::string(kFormat));
    f.write_attribute("/", "schema_version", kSchemaVersion);
    f.write_attribute("/", "input", int64_t{model.shape.input});
    f.write_attribute("/", "hidden", int64_t{model.shape.hidden});
    f.write_attribute("/", "fc", int64_t{model.shape.fc});
    f.write_attribute("/", "architecture", std::string(to_string(model.shape.architecture)));
    const TrackNormalisation& n = model.normalisation;
    f.write_attribute("/", "x0", n.x0);
    f.write_attribute("/", "y0", n.y0);
    f.write_attribute("/", "position_scale", n.position_scale);
    f.write_attribute("/", "t0", n.t0);
    f.write_attribute("/", "time_scale", n.time_scale);
    f.write_attribute("/", "training", training_json);
    std::vector<float> buf;
    for (const Block& b : blocks(model.shape)) {
      const float* p = model.params.data() + b.offset;
      if (b.cols == 0) {
        f.write(b.name, p, static_cast<hsize_t>(b.rows));
      } else {
        buf.resize(static_cast<std::size_t>(b.rows * b.cols));
        for (int64_t r = 0; r < b.rows; ++r)
          for (int64_t c = 0; c < b.cols; ++c) buf[r * b.cols + c] = p[c * b.rows + r];
        f.write(b.name, buf.data(), static_cast<hsize_t>(b.rows), static_cast<hsize_t>(b.cols));
      }
    }
    f.close();
  });
}

LoadedSiameseModel read_siamese_model(const std::string& path) {
  siamese_h5::File f = siamese_h5::File::open_read(path);
  const std::string format = f.read_string_attribute("/", "format");
  if (format != kFormat)
    throw InputError(path + ": attribute /@format is '" + format + "', expected '" + kFormat + "'");
  const int64_t version = f.read_int_attribute("/", "schema_version");
  if (version != kSchemaVersion)
    throw InputError(path + ": schema_version " + std::to_string(version) + " is not supported (expected " +
                     std::to_string(kSchemaVersion) + ")");
  LoadedSiameseModel out;
  SiameseModel<float>& m = out.model;
  auto dim = [&](const char* name) {
    const int64_t v = f.read_int_attribute("/", name);
    if (v < 1 || v > 65536)
      throw InputError(path + ": attribute /@" + std::string(name) + " = " + std::to_string(v) +
                       " is out of range");
    return static_cast<int>(v);
  };
  m.shape.input = dim("input");
  m.shape.hidden = dim("hidden");
  m.shape.fc = dim("fc");
  try {
    m.shape.architecture = parse_pair_architecture(f.read_string_attribute("/", "architecture"));
  } catch (const InputError& e) {
    throw InputError(path + ": attribute /@" + e.what());
  }
  try {
    m.shape.validate();
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  m.normalisation.x0 = f.read_double_attribute("/", "x0");
  m.normalisation.y0 = f.read_double_attribute("/", "y0");
  m.normalisation.position_scale = f.read_double_attribute("/", "position_scale");
  m.normalisation.t0 = f.read_double_attribute("/", "t0");
  m.normalisation.time_scale = f.read_double_attribute("/", "time_scale");
  try {
    m.normalisation.validate();
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  out.training_json = f.read_string_attribute("/", "training");
  m.params.assign(static_cast<std::size_t>(m.shape.parameter_count()), 0.0f);
  for (const Block& b : blocks(m.shape)) {
    std::vector<hsize_t> want{static_cast<hsize_t>(b.rows)};
    if (b.cols) want.push_back(static_cast<hsize_t>(b.cols));
    const std::vector<float> v = f.read_float(b.name, want);
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k]))
        throw InputError(path + ": dataset " + b.name + " has a non-finite value at element " +
                         std::to_string(k));
    float* p = m.params.data() + b.offset;
    if (b.cols == 0) {
      std::copy(v.begin(), v.end(), p);
    } else {
      for (int64_t r = 0; r < b.rows; ++r)
        for (int64_t c = 0; c < b.cols; ++c) p[c * b.rows + r] = v[r * b.cols + c];
    }
  }
  return out;
}

}  // namespace trackassoc
