// Seed 003 pair data set files (see siamese_dataset_file.hpp).
#include "io/siamese_dataset_file.hpp"

#include <limits>
#include <span>

#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/isolated_run.hpp"
#include "kernels/core/error.hpp"
#include "kernels/learning/siamese_training.hpp"

namespace trackassoc {
namespace {

using h5::Group;

constexpr const char* kFormat = "trackassoc-seed003-dataset";
constexpr int32_t kSchemaVersion = 1;

template <class T>
void write_1d(const Group& g, const std::string& name, const std::vector<T>& v) {
  g.write_dataset(name, std::span<const T>(v), {static_cast<hsize_t>(v.size())});
}

void write_tracks(const Group& g, const TrackSequences& tr, const std::vector<int32_t>& target) {
  write_1d(g, "x", tr.x);
  write_1d(g, "y", tr.y);
  write_1d(g, "t", tr.t);
  write_1d(g, "offset", tr.offset);
  write_1d(g, "target", target);
}

void write_pairs(const Group& g, const PairSet& p, const std::vector<uint8_t>& kind) {
  write_1d(g, "left", p.left);
  write_1d(g, "right", p.right);
  write_1d(g, "label", p.label);
  write_1d(g, "kind", kind);
}

// A 1-D dataset of `rows` entries (any when rows < 0): doubles, or integers in [lo, hi].
std::vector<double> read_doubles(const Group& g, const std::string& name, int64_t rows = -1) {
  std::vector<hsize_t> dims;
  std::vector<double> v = g.read_doubles(name, 1, dims);
  if (rows >= 0 && dims[0] != static_cast<hsize_t>(rows))
    g.fail(name, "has " + std::to_string(dims[0]) + " entries, expected " + std::to_string(rows));
  return v;
}

template <class T>
std::vector<T> read_ints(const Group& g, const std::string& name, int64_t rows, int64_t lo, int64_t hi) {
  std::vector<hsize_t> dims;
  const std::vector<int64_t> wide = g.read_integers(name, 1, dims);
  if (rows >= 0 && dims[0] != static_cast<hsize_t>(rows))
    g.fail(name, "has " + std::to_string(dims[0]) + " entries, expected " + std::to_string(rows));
  std::vector<T> out(wide.size());
  for (std::size_t k = 0; k < wide.size(); ++k) {
    if (wide[k] < lo || wide[k] > hi)
      g.fail(name, "entry " + std::to_string(k) + " = " + std::to_string(wide[k]) + " is out of range [" +
                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
    out[k] = static_cast<T>(wide[k]);
  }
  return out;
}

constexpr int64_t kInt32Max = std::numeric_limits<int32_t>::max();

void read_tracks(const std::string& file, const Group& g, TrackSequences& tr, std::vector<int32_t>& target) {
  tr.x = read_doubles(g, "x");
  const auto n = static_cast<int64_t>(tr.x.size());
  tr.y = read_doubles(g, "y", n);
  tr.t = read_doubles(g, "t", n);
  tr.offset = read_ints<int64_t>(g, "offset", -1, 0, n);
  if (tr.offset.empty()) g.fail("offset", "is empty (expected tracks + 1 entries)");
  target = read_ints<int32_t>(g, "target", static_cast<int64_t>(tr.offset.size()) - 1, -1, kInt32Max);
  for (std::size_t k = 0; k + 1 < tr.offset.size(); ++k)
    if (tr.offset[k + 1] < tr.offset[k]) g.fail("offset", "decreases at entry " + std::to_string(k + 1));
  try {
    tr.validate(g.path().c_str());
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

void read_pairs(const Group& g, PairSet& p, std::vector<uint8_t>& kind) {
  p.left = read_ints<int32_t>(g, "left", -1, 0, kInt32Max);
  const auto n = static_cast<int64_t>(p.left.size());
  p.right = read_ints<int32_t>(g, "right", n, 0, kInt32Max);
  p.label = read_ints<uint8_t>(g, "label", n, 0, 1);
  kind = read_ints<uint8_t>(g, "kind", n, 0, 2);
}

Seed003Dataset read_in_process(const std::string& path) {
  h5::File f = h5::File::open_read_only(path);
  const Group root = f.root();
  h5::require_format(root, path, kFormat, kSchemaVersion, "seed 003 data set");
  Seed003Dataset d;
  d.generator_json = root.read_string_attribute("generator");
  read_tracks(path, root.open_group("radar1"), d.radar1, d.target1);
  read_tracks(path, root.open_group("radar2"), d.radar2, d.target2);
  const Group pairs = root.open_group("pairs");
  read_pairs(pairs.open_group("train"), d.train, d.train_kind);
  read_pairs(pairs.open_group("test"), d.test, d.test_kind);
  try {
    validate_pairs(d.train, d.radar1, d.radar2, "/pairs/train");
    validate_pairs(d.test, d.radar1, d.radar2, "/pairs/test");
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return d;
}

}  // namespace

void write_seed003_dataset(const std::string& path, const Seed003Dataset& d) {
  write_atomically(path, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const Group root = f.root();
    root.write_attribute("format", std::string(kFormat));
    root.write_attribute("schema_version", kSchemaVersion);
    root.write_attribute("generator", d.generator_json);
    write_tracks(root.create_group("radar1"), d.radar1, d.target1);
    write_tracks(root.create_group("radar2"), d.radar2, d.target2);
    const Group pairs = root.create_group("pairs");
    write_pairs(pairs.create_group("train"), d.train, d.train_kind);
    write_pairs(pairs.create_group("test"), d.test, d.test_kind);
    f.close();
  });
}

Seed003Dataset read_seed003_dataset(const std::string& path) {
  // A damaged file can hang or crash libhdf5 1.10: read it in a forked child first.
  return read_isolated(path, read_in_process);
}

}  // namespace trackassoc
