// Seed 003 pair data set files (see siamese_dataset_file.hpp).
#include "io/siamese_dataset_file.hpp"

#include "io/atomic_file.hpp"
#include "io/siamese_hdf5.hpp"
#include "kernels/error.hpp"
#include "kernels/siamese_training.hpp"

namespace trackassoc {
namespace {

constexpr const char* kFormat = "trackassoc-seed003-dataset";
constexpr int64_t kSchemaVersion = 1;

void write_tracks(siamese_h5::File& f, const std::string& g, const TrackSequences& tr,
                  const std::vector<int32_t>& target) {
  f.write(g + "/x", tr.x.data(), tr.x.size());
  f.write(g + "/y", tr.y.data(), tr.y.size());
  f.write(g + "/t", tr.t.data(), tr.t.size());
  f.write(g + "/offset", tr.offset.data(), tr.offset.size());
  f.write(g + "/target", target.data(), target.size());
}

void write_pairs(siamese_h5::File& f, const std::string& g, const PairSet& p,
                 const std::vector<uint8_t>& kind) {
  f.write(g + "/left", p.left.data(), p.left.size());
  f.write(g + "/right", p.right.data(), p.right.size());
  f.write(g + "/label", p.label.data(), p.label.size());
  f.write(g + "/kind", kind.data(), kind.size());
}

void read_tracks(const siamese_h5::File& f, const std::string& g, TrackSequences& tr,
                 std::vector<int32_t>& target) {
  tr.x = f.read_double(g + "/x");
  const std::vector<hsize_t> n{static_cast<hsize_t>(tr.x.size())};
  tr.y = f.read_double(g + "/y", n);
  tr.t = f.read_double(g + "/t", n);
  tr.offset = f.read_int64(g + "/offset");
  if (tr.offset.empty()) throw InputError(f.path() + ": dataset " + g + "/offset is empty");
  target = f.read_int32(g + "/target", {static_cast<hsize_t>(tr.offset.size() - 1)});
  for (std::size_t k = 0; k + 1 < tr.offset.size(); ++k)
    if (tr.offset[k + 1] < tr.offset[k])
      throw InputError(f.path() + ": dataset " + g + "/offset decreases at row " + std::to_string(k + 1));
  try {
    tr.validate(g.c_str());
  } catch (const InputError& e) {
    throw InputError(f.path() + ": " + e.what());
  }
}

void read_pairs(const siamese_h5::File& f, const std::string& g, PairSet& p, std::vector<uint8_t>& kind) {
  p.left = f.read_int32(g + "/left");
  const std::vector<hsize_t> n{static_cast<hsize_t>(p.left.size())};
  p.right = f.read_int32(g + "/right", n);
  p.label = f.read_uint8(g + "/label", n);
  kind = f.read_uint8(g + "/kind", n);
}

}  // namespace

void write_seed003_dataset(const std::string& path, const Seed003Dataset& d) {
  write_atomically(path, [&](const std::string& tmp) {
    siamese_h5::File f = siamese_h5::File::create(tmp);
    f.write_attribute("/", "format", std::string(kFormat));
    f.write_attribute("/", "schema_version", kSchemaVersion);
    f.write_attribute("/", "generator", d.generator_json);
    write_tracks(f, "/radar1", d.radar1, d.target1);
    write_tracks(f, "/radar2", d.radar2, d.target2);
    write_pairs(f, "/pairs/train", d.train, d.train_kind);
    write_pairs(f, "/pairs/test", d.test, d.test_kind);
    f.close();
  });
}

Seed003Dataset read_seed003_dataset(const std::string& path) {
  const siamese_h5::File f = siamese_h5::File::open_read(path);
  const std::string format = f.read_string_attribute("/", "format");
  if (format != kFormat)
    throw InputError(path + ": attribute /@format is '" + format + "', expected '" + kFormat + "'");
  const int64_t version = f.read_int_attribute("/", "schema_version");
  if (version != kSchemaVersion)
    throw InputError(path + ": schema_version " + std::to_string(version) + " is not supported");
  Seed003Dataset d;
  d.generator_json = f.read_string_attribute("/", "generator");
  read_tracks(f, "/radar1", d.radar1, d.target1);
  read_tracks(f, "/radar2", d.radar2, d.target2);
  read_pairs(f, "/pairs/train", d.train, d.train_kind);
  read_pairs(f, "/pairs/test", d.test, d.test_kind);
  try {
    validate_pairs(d.train, d.radar1, d.radar2, "/pairs/train");
    validate_pairs(d.test, d.radar1, d.radar2, "/pairs/test");
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return d;
}

}  // namespace trackassoc
