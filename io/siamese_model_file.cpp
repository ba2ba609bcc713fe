// Siamese model files (see siamese_model_file.hpp).
#include "io/siamese_model_file.hpp"

#include <cmath>

#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/isolated_run.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using h5::Group;

constexpr const char* kFormat = "trackassoc-siamese-model";
constexpr int32_t kSchemaVersion = 1;

// A parameter block of the flat vector: column-major rows×cols in memory, row-major in the file.
struct Block {
  std::vector<std::string> group;  // {"branch", "forward"} or {"head"}
  std::string name;
  int64_t offset, rows, cols;  // cols == 0: a vector
};

std::vector<Block> blocks(const SiameseShape& s) {
  const int64_t H = s.hidden, F = s.input, per_dir = s.lstm().parameter_count();
  std::vector<Block> out;
  const char* dirs[2] = {"forward", "backward"};
  for (int d = 0; d < s.directions(); ++d) {
    const int64_t o = d * per_dir;
    out.push_back({{"branch", dirs[d]}, "Wx", o, 4 * H, F});
    out.push_back({{"branch", dirs[d]}, "Wh", o + 4 * H * F, 4 * H, H});
    out.push_back({{"branch", dirs[d]}, "b", o + 4 * H * F + 4 * H * H, 4 * H, 0});
  }
  const int64_t h = s.branch_parameter_count(), fc = s.fc, e = s.embedding();
  out.push_back({{"head"}, "W1", h, fc, e});
  out.push_back({{"head"}, "b1", h + fc * e, fc, 0});
  out.push_back({{"head"}, "w2", h + fc * e + fc, fc, 0});
  out.push_back({{"head"}, "b2", h + fc * e + 2 * fc, 1, 0});
  return out;
}

// The group of a block, created (writing) or opened (reading) level by level from the root.
Group block_group(const Group& root, const Block& b, bool create) {
  Group g = create ? (root.has(b.group[0]) ? root.open_group(b.group[0]) : root.create_group(b.group[0]))
                   : root.open_group(b.group[0]);
  for (std::size_t k = 1; k < b.group.size(); ++k)
    g = create ? (g.has(b.group[k]) ? g.open_group(b.group[k]) : g.create_group(b.group[k]))
               : g.open_group(b.group[k]);
  return g;
}

LoadedSiameseModel read_in_process(const std::string& path) {
  h5::File f = h5::File::open_read_only(path);
  const Group root = f.root();
  h5::require_format(root, path, kFormat, kSchemaVersion, "Siamese model file");
  LoadedSiameseModel out;
  SiameseModel<float>& m = out.model;
  auto dim = [&](const char* name) {
    const int64_t v = root.read_integer_attribute(name);
    if (v < 1 || v > 65536)
      throw InputError(path + ": / attribute " + std::string(name) + " = " + std::to_string(v) +
                       " is out of range [1, 65536]");
    return static_cast<int>(v);
  };
  m.shape.input = dim("input");
  m.shape.hidden = dim("hidden");
  m.shape.fc = dim("fc");
  try {
    m.shape.architecture =
        parse_enum<PairArchitecture>(root.read_string_attribute("architecture"), "architecture");
    m.shape.validate();
    m.normalisation.x0 = root.read_double_attribute("x0");
    m.normalisation.y0 = root.read_double_attribute("y0");
    m.normalisation.position_scale = root.read_double_attribute("position_scale");
    m.normalisation.t0 = root.read_double_attribute("t0");
    m.normalisation.time_scale = root.read_double_attribute("time_scale");
    m.normalisation.validate();
  } catch (const InputError& e) {
    const std::string what = e.what();
    throw InputError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
  out.training_json = root.read_string_attribute("training");
  m.params.assign(static_cast<std::size_t>(m.shape.parameter_count()), 0.0f);
  for (const Block& b : blocks(m.shape)) {
    const Group g = block_group(root, b, false);
    std::vector<hsize_t> want{static_cast<hsize_t>(b.rows)}, dims;
    if (b.cols) want.push_back(static_cast<hsize_t>(b.cols));
    if (g.dataset_shape(b.name) != want)  // checked before reading, so no oversized allocation
      g.fail(b.name,
             "has shape " + h5::shape_text(g.dataset_shape(b.name)) + ", expected " + h5::shape_text(want));
    const std::vector<float> v = g.read_floats(b.name, static_cast<int>(want.size()), dims);
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k])) g.fail(b.name, "has a non-finite value at element " + std::to_string(k));
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

}  // namespace

void write_siamese_model(const std::string& path, const SiameseModel<float>& model,
                         const std::string& training_json) {
  model.shape.validate();
  model.normalisation.validate();
  require(static_cast<int64_t>(model.params.size()) == model.shape.parameter_count(), "model",
          "parameter vector size does not match its shape");
  write_atomically(path, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const Group root = f.root();
    root.write_attribute("format", std::string(kFormat));
    root.write_attribute("schema_version", kSchemaVersion);
    root.write_attribute("input", int32_t{model.shape.input});
    root.write_attribute("hidden", int32_t{model.shape.hidden});
    root.write_attribute("fc", int32_t{model.shape.fc});
    root.write_attribute("architecture", std::string(enum_name(model.shape.architecture)));
    const TrackNormalisation& n = model.normalisation;
    root.write_attribute("x0", n.x0);
    root.write_attribute("y0", n.y0);
    root.write_attribute("position_scale", n.position_scale);
    root.write_attribute("t0", n.t0);
    root.write_attribute("time_scale", n.time_scale);
    root.write_attribute("training", training_json);
    std::vector<float> buf;
    for (const Block& b : blocks(model.shape)) {
      const Group g = block_group(root, b, true);
      const float* p = model.params.data() + b.offset;
      if (b.cols == 0) {
        g.write_dataset(b.name, std::span<const float>(p, static_cast<std::size_t>(b.rows)),
                        {static_cast<hsize_t>(b.rows)});
      } else {
        buf.resize(static_cast<std::size_t>(b.rows * b.cols));
        for (int64_t r = 0; r < b.rows; ++r)
          for (int64_t c = 0; c < b.cols; ++c) buf[r * b.cols + c] = p[c * b.rows + r];
        g.write_dataset(b.name, std::span<const float>(buf),
                        {static_cast<hsize_t>(b.rows), static_cast<hsize_t>(b.cols)});
      }
    }
    f.close();
  });
}

LoadedSiameseModel read_siamese_model(const std::string& path) {
  // A damaged file can hang or crash libhdf5 1.10: read it in a forked child first.
  return read_isolated(path, read_in_process);
}

}  // namespace trackassoc
