#include "io/hdf5_wrapper.hpp"

#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>

#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc::h5 {
namespace {

std::string class_name(H5T_class_t c) {
  switch (c) {
    case H5T_INTEGER:
      return "integer";
    case H5T_FLOAT:
      return "float";
    case H5T_STRING:
      return "string";
    case H5T_BITFIELD:
      return "bitfield";
    case H5T_OPAQUE:
      return "opaque";
    case H5T_COMPOUND:
      return "compound";
    case H5T_REFERENCE:
      return "reference";
    case H5T_ENUM:
      return "enum";
    case H5T_VLEN:
      return "variable-length sequence";
    case H5T_ARRAY:
      return "array";
    default:
      return "unknown type";
  }
}

// Object creation properties shared by groups and datasets: no modification times.
Handle creation_properties(hid_t cls, const std::string& where) {
  Handle p(H5Pcreate(cls), H5Pclose);
  if (!p.valid() || H5Pset_obj_track_times(p.get(), false) < 0)
    throw InputError(where + ": cannot create HDF5 property list");
  return p;
}

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}

}  // namespace

void silence_library_errors() {
  static std::once_flag once;
  std::call_once(once, [] {
    // No library shutdown at exit: after a failed H5Fclose (a full disk while flushing) the file
    // stays registered half-destroyed, and H5_term_library, run by atexit, crashed on it after the
    // error had been printed. Every file is closed explicitly (File::close, Handle) or was a
    // temporary output that write_atomically removes, so the shutdown has nothing left to do.
    // Must come before the library's first initialisation; this is the wrapper's first call.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  });
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    close();
    id_ = o.id_;
    closer_ = o.closer_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

herr_t Handle::close() {
  herr_t status = 0;
  if (id_ >= 0 && closer_) status = closer_(id_);
  id_ = H5I_INVALID_HID;
  return status;
}

std::string shape_text(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "a scalar";
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i) s += 'x';
    s += std::to_string(dims[i]);
  }
  return s;
}

// ---------------------------------------------------------------- File

File File::create(const std::string& path) {
  silence_library_errors();
  // The file creation property list is a group creation list for the root group: no times there either.
  Handle fcpl = creation_properties(H5P_FILE_CREATE, path);
  // The 1.8 file format: superblock v2 and object headers v2 carry checksums, so a corrupted
  // header is reported by the library instead of being decoded; HDF5 >= 1.8 (h5py, MATLAB) reads it.
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V18) < 0)
    throw InputError(path + ": cannot set HDF5 file format version");
  Handle f(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose);
  if (!f.valid()) throw InputError(path + ": cannot create HDF5 file (is the folder writable?)");
  return File(path, std::move(f));
}

File File::open_read_only(const std::string& path) {
  silence_library_errors();
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": file does not exist");
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  const auto size = fs::file_size(path, ec);
  if (!ec && size == 0) throw InputError(path + ": empty file (expected an HDF5 track file)");
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 <= 0) throw InputError(path + ": not an HDF5 file (no HDF5 signature found)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.valid()) throw InputError(path + ": cannot open HDF5 file (truncated or corrupt?)");
  return File(path, std::move(f));
}

Group File::root() const {
  Handle g(H5Gopen2(handle_.get(), "/", H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw InputError(path_ + ": cannot open the root group (corrupt file?)");
  return Group(path_, std::move(g), "/");
}

void File::close() {
  if (!handle_.valid()) return;
  if (H5Fflush(handle_.get(), H5F_SCOPE_LOCAL) < 0 || handle_.close() < 0)
    throw InputError(path_ + ": cannot flush and close the HDF5 file (disk full?)");
}

// ---------------------------------------------------------------- Group: writing

void Group::fail(const std::string& object, const std::string& what) const {
  throw InputError(file_path_ + ": " + child_path(object) + ": " + what);
}

Group Group::create_group(const std::string& name, bool track_order) const {
  Handle gcpl = creation_properties(H5P_GROUP_CREATE, file_path_ + ": " + child_path(name));
  if (track_order &&
      H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED) < 0)
    fail(name, "cannot set link creation order");
  Handle g(H5Gcreate2(id(), name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(name, "cannot create group");
  return Group(file_path_, std::move(g), child_path(name));
}

// Strings are written variable-length UTF-8, which h5py returns as `str` (fixed-length strings
// come back as `bytes`, a papercut for every Python user). Variable-length data lives in the
// global heap, which has no checksum, and libhdf5 1.10 hangs or overruns buffers on a corrupted
// global heap (found by tests/fuzz/fuzz_track_file): read_track_file therefore reads untrusted
// files in a forked child first (io/isolated_run.hpp), so such a file is an InputError, not a crash.
void Group::write_attribute(const std::string& name, const std::string& value) const {
  const std::string where = path_ + " attribute " + name;
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), H5T_VARIABLE) < 0 ||
      H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    throw InputError(file_path_ + ": " + where + ": cannot create HDF5 string type");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(id(), name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const char* text = value.c_str();
  if (!space.valid() || !attr.valid() || H5Awrite(attr.get(), type.get(), &text) < 0)
    throw InputError(file_path_ + ": " + where + ": cannot write string attribute");
}

namespace {
void write_scalar_attribute(hid_t loc, const std::string& file, const std::string& where,
                            const std::string& name, hid_t file_type, hid_t mem_type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!space.valid() || !attr.valid() || H5Awrite(attr.get(), mem_type, value) < 0)
    throw InputError(file + ": " + where + " attribute " + name + ": cannot write attribute");
}
}  // namespace

void Group::write_attribute(const std::string& name, double value) const {
  write_scalar_attribute(id(), file_path_, path_, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}
void Group::write_attribute(const std::string& name, int32_t value) const {
  write_scalar_attribute(id(), file_path_, path_, name, H5T_STD_I32LE, H5T_NATIVE_INT32, &value);
}
void Group::write_attribute(const std::string& name, uint64_t value) const {
  write_scalar_attribute(id(), file_path_, path_, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value);
}

void Group::write_numeric(const std::string& name, hid_t file_type, hid_t mem_type, const void* data,
                          std::vector<hsize_t> dims, std::size_t count) const {
  hsize_t expected = 1;
  for (hsize_t d : dims) expected *= d;
  if (dims.empty() || dims.size() > 32 || expected != count)
    fail(name, "internal: " + std::to_string(count) + " values do not fill shape " + shape_text(dims));
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl = creation_properties(H5P_DATASET_CREATE, file_path_ + ": " + child_path(name));
  Handle set(H5Dcreate2(id(), name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
             H5Dclose);
  if (!space.valid() || !set.valid()) fail(name, "cannot create dataset of shape " + shape_text(dims));
  if (count > 0 && H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(name, "cannot write dataset (disk full?)");
  if (set.close() < 0) fail(name, "cannot close dataset (disk full?)");
}

void Group::write_dataset(const std::string& name, std::span<const int32_t> data,
                          std::vector<hsize_t> dims) const {
  write_numeric(name, H5T_STD_I32LE, H5T_NATIVE_INT32, data.data(), std::move(dims), data.size());
}
void Group::write_dataset(const std::string& name, std::span<const double> data,
                          std::vector<hsize_t> dims) const {
  write_numeric(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data.data(), std::move(dims), data.size());
}
void Group::write_dataset(const std::string& name, std::span<const float> data,
                          std::vector<hsize_t> dims) const {
  write_numeric(name, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, data.data(), std::move(dims), data.size());
}
void Group::write_dataset(const std::string& name, std::span<const int64_t> data,
                          std::vector<hsize_t> dims) const {
  write_numeric(name, H5T_STD_I64LE, H5T_NATIVE_INT64, data.data(), std::move(dims), data.size());
}
void Group::write_dataset(const std::string& name, std::span<const uint8_t> data,
                          std::vector<hsize_t> dims) const {
  write_numeric(name, H5T_STD_U8LE, H5T_NATIVE_UINT8, data.data(), std::move(dims), data.size());
}

// ---------------------------------------------------------------- Group: reading

bool Group::has(const std::string& name) const {
  // H5Lexists is only safe on a single path component; names here never contain '/'.
  const htri_t r = H5Lexists(id(), name.c_str(), H5P_DEFAULT);
  if (r < 0) fail(name, "cannot look up link (corrupt file?)");
  return r > 0;
}

bool Group::is_group(const std::string& name) const {
  if (!has(name)) return false;
  H5O_info_t info;
  if (H5Oget_info_by_name(id(), name.c_str(), &info, H5P_DEFAULT) < 0)
    fail(name, "cannot read object header");
  return info.type == H5O_TYPE_GROUP;
}

bool Group::has_attribute(const std::string& name) const {
  const htri_t r = H5Aexists(id(), name.c_str());
  if (r < 0) throw InputError(file_path_ + ": " + path_ + ": cannot look up attribute " + name);
  return r > 0;
}

Group Group::open_group(const std::string& name) const {
  if (!has(name)) fail(name, "missing group");
  if (!is_group(name)) fail(name, "expected a group, found another kind of object");
  Handle g(H5Gopen2(id(), name.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(name, "cannot open group");
  return Group(file_path_, std::move(g), child_path(name));
}

std::vector<std::string> Group::children() const {
  std::vector<std::string> names;
  H5_index_t index = H5_INDEX_NAME;
  Handle gcpl(H5Gget_create_plist(id()), H5Pclose);
  unsigned flags = 0;
  if (gcpl.valid() && H5Pget_link_creation_order(gcpl.get(), &flags) >= 0 && (flags & H5P_CRT_ORDER_INDEXED))
    index = H5_INDEX_CRT_ORDER;
  hsize_t position = 0;
  if (H5Literate(id(), index, H5_ITER_INC, &position, collect_name, &names) < 0)
    throw InputError(file_path_ + ": " + path_ + ": cannot list the group's members (corrupt file?)");
  return names;
}

std::string Group::read_string_attribute(const std::string& name) const {
  const std::string where = file_path_ + ": " + path_ + " attribute " + name;
  if (!has_attribute(name)) throw InputError(where + ": missing");
  Handle attr(H5Aopen(id(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) throw InputError(where + ": cannot open");
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (!type.valid() || !space.valid()) throw InputError(where + ": cannot read its type");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_STRING) throw InputError(where + ": expected a string, found " + class_name(cls));
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw InputError(where + ": expected a single string");
  const htri_t variable = H5Tis_variable_str(type.get());
  if (variable < 0) throw InputError(where + ": cannot read its type");
  if (variable > 0) {
    // Files from other writers (h5py's default for str): the memory type is the file's own.
    Handle mem(H5Tcopy(type.get()), H5Tclose);
    char* p = nullptr;
    if (!mem.valid() || H5Aread(attr.get(), mem.get(), &p) < 0) throw InputError(where + ": cannot read");
    std::string value = p ? p : "";
    // Frees the library-allocated string (H5Dvlen_reclaim is the 1.10 spelling).
    H5free_memory(p);
    return value;
  }
  const std::size_t size = H5Tget_size(type.get());
  if (size == 0 || size > (std::size_t{1} << 26)) throw InputError(where + ": implausible string size");
  std::vector<char> buffer(size + 1, '\0');
  Handle mem(H5Tcopy(type.get()), H5Tclose);
  if (!mem.valid() || H5Aread(attr.get(), mem.get(), buffer.data()) < 0)
    throw InputError(where + ": cannot read");
  return std::string(buffer.data(), strnlen(buffer.data(), size));
}

Handle Group::open_numeric_attribute(const std::string& name, NumberClass accepted) const {
  const std::string where = file_path_ + ": " + path_ + " attribute " + name;
  if (!has_attribute(name)) throw InputError(where + ": missing");
  Handle attr(H5Aopen(id(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) throw InputError(where + ": cannot open");
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (!type.valid() || !space.valid()) throw InputError(where + ": cannot read its type");
  const H5T_class_t cls = H5Tget_class(type.get());
  const bool ok = cls == H5T_INTEGER || (accepted == NumberClass::kIntegerOrFloat && cls == H5T_FLOAT);
  if (!ok)
    throw InputError(where + ": expected " + (accepted == NumberClass::kInteger ? "an integer" : "a number") +
                     ", found " + class_name(cls));
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw InputError(where + ": expected a single value");
  return attr;
}

double Group::read_double_attribute(const std::string& name) const {
  Handle attr = open_numeric_attribute(name, NumberClass::kIntegerOrFloat);
  double v = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v) < 0)
    throw InputError(file_path_ + ": " + path_ + " attribute " + name + ": cannot read");
  return v;
}

int64_t Group::read_integer_attribute(const std::string& name) const {
  Handle attr = open_numeric_attribute(name, NumberClass::kInteger);
  int64_t v = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_INT64, &v) < 0)
    throw InputError(file_path_ + ": " + path_ + " attribute " + name + ": cannot read");
  return v;
}

uint64_t Group::read_unsigned_attribute(const std::string& name) const {
  Handle attr = open_numeric_attribute(name, NumberClass::kInteger);
  uint64_t v = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_UINT64, &v) < 0)
    throw InputError(file_path_ + ": " + path_ + " attribute " + name + ": cannot read");
  return v;
}

std::vector<hsize_t> Group::dataset_shape(const std::string& name) const {
  if (!has(name)) fail(name, "missing dataset");
  Handle set(H5Dopen2(id(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid()) fail(name, "expected a dataset, cannot open it");
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank < 0 || rank > 32) fail(name, "cannot read dataspace");
  std::vector<hsize_t> dims(rank);
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
    fail(name, "cannot read dataspace");
  return dims;
}

std::size_t Group::table_rows(std::initializer_list<const char*> columns) const {
  const char* reference = *columns.begin();
  const std::vector<hsize_t> first = dataset_shape(reference);
  if (first.empty()) fail(reference, "expected a 1-D or 2-D dataset, found a scalar");
  const hsize_t rows = first[0];
  double elements = 0.0, largest_matrix = 0.0;
  for (const char* name : columns) {
    if (!has(name)) continue;  // optional columns; a missing required one is reported when read
    const std::vector<hsize_t> dims = dataset_shape(name);
    if (dims.empty() || dims[0] != rows)
      fail(name, "expected " + std::to_string(rows) + " rows (as " + child_path(reference) + "), found " +
                     (dims.empty() ? std::string("a scalar") : std::to_string(dims[0])));
    double n = 1.0;
    for (hsize_t d : dims) n *= static_cast<double>(d);
    elements += n;
    if (dims.size() > 1) largest_matrix = std::max(largest_matrix, n);
  }
  // A matrix (state, cov) is read row-major and then laid out by columns: both at once, briefly.
  require_memory_beside_held(0.0, (elements + largest_matrix) * 8.0,
                             file_path_ + ": " + path_ + " (" + std::to_string(rows) + " rows of " +
                                 std::to_string(columns.size()) + " columns)");
  return static_cast<std::size_t>(rows);
}

Handle Group::open_numeric_dataset(const std::string& name, NumberClass accepted, int rank,
                                   std::vector<hsize_t>& dims, std::size_t& count) const {
  dims = dataset_shape(name);
  Handle set(H5Dopen2(id(), name.c_str(), H5P_DEFAULT), H5Dclose);
  Handle type(set.valid() ? H5Dget_type(set.get()) : H5I_INVALID_HID, H5Tclose);
  if (!type.valid()) fail(name, "cannot read its dtype");
  const H5T_class_t cls = H5Tget_class(type.get());
  const bool ok = cls == H5T_INTEGER || (accepted == NumberClass::kIntegerOrFloat && cls == H5T_FLOAT);
  if (!ok)
    fail(name, std::string("expected ") +
                   (accepted == NumberClass::kInteger ? "integer" : "numeric (integer or float)") +
                   " values, found " + class_name(cls));
  if (static_cast<int>(dims.size()) != rank)
    fail(name, "expected a " + std::to_string(rank) + "-D dataset, found shape " + shape_text(dims));
  count = 1;
  for (hsize_t d : dims) {
    if (d > kMaxDatasetElements || (d > 0 && count > kMaxDatasetElements / d))
      fail(name, "shape " + shape_text(dims) + " exceeds the reader's limit of 2^28 elements");
    count *= d;
  }
  return set;
}

// A header may declare far more rows than the file holds (chunks never written read back as fill
// values): the stored bytes must cover the declared ones, or, for a filtered (compressed) dataset,
// a thousandth of them (deflate's ratio cannot exceed 1032:1). Checked before anything is allocated.
void Group::require_stored(const Handle& set, const std::string& name, const std::vector<hsize_t>& dims,
                           std::size_t count) const {
  Handle type(H5Dget_type(set.get()), H5Tclose);
  Handle dcpl(H5Dget_create_plist(set.get()), H5Pclose);
  if (!type.valid() || !dcpl.valid()) fail(name, "cannot read its dtype or creation properties");
  const int filters = H5Pget_nfilters(dcpl.get());
  const double declared = static_cast<double>(count) * static_cast<double>(H5Tget_size(type.get()));
  const double stored = static_cast<double>(H5Dget_storage_size(set.get()));
  const double needed = filters > 0 ? declared / 1100.0 : declared;
  if (filters < 0 || stored < needed)
    fail(name, "shape " + shape_text(dims) + " declares " + size_text(bytes_of(declared, 1)) +
                   " but the file stores " + size_text(bytes_of(stored, 1)) +
                   " of it (unwritten chunks, or a truncated or corrupt file)");
}

template <typename T>
std::vector<T> Group::read_typed(const std::string& name, NumberClass accepted, hid_t mem_type, int rank,
                                 std::vector<hsize_t>& dims) const {
  std::size_t count = 0;
  Handle set = open_numeric_dataset(name, accepted, rank, dims, count);
  if (count > 0) require_stored(set, name, dims, count);
  require_memory_beside_held(0.0, static_cast<double>(count) * sizeof(T),
                             file_path_ + ": " + child_path(name) + " (shape " + shape_text(dims) + ")");
  std::vector<T> out;
  try {
    out.resize(count);
  } catch (const std::bad_alloc&) {
    fail(name, "not enough memory for shape " + shape_text(dims));
  }
  if (count > 0 && H5Dread(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(name, "cannot read the data (truncated or corrupt file?)");
  return out;
}

std::vector<double> Group::read_doubles(const std::string& name, int rank, std::vector<hsize_t>& dims) const {
  return read_typed<double>(name, NumberClass::kIntegerOrFloat, H5T_NATIVE_DOUBLE, rank, dims);
}
std::vector<float> Group::read_floats(const std::string& name, int rank, std::vector<hsize_t>& dims) const {
  return read_typed<float>(name, NumberClass::kIntegerOrFloat, H5T_NATIVE_FLOAT, rank, dims);
}
std::vector<int64_t> Group::read_integers(const std::string& name, int rank,
                                          std::vector<hsize_t>& dims) const {
  return read_typed<int64_t>(name, NumberClass::kInteger, H5T_NATIVE_INT64, rank, dims);
}

void require_format(const Group& root, const std::string& path, const std::string& format, int64_t version,
                    const std::string& what) {
  if (!root.has_attribute("format"))
    throw InputError(path + ": not a " + what + " (the root has no 'format' attribute; expected '" + format +
                     "')");
  const std::string found = root.read_string_attribute("format");
  if (found != format)
    throw InputError(path + ": / attribute format is " + quoted_preview(found, 80) + ", expected '" + format +
                     "' (a " + what + ")");
  const int64_t v = root.read_integer_attribute("schema_version");
  if (v != version)
    throw InputError(path + ": schema_version " + std::to_string(v) + " is not supported (expected " +
                     std::to_string(version) + ")");
}

}  // namespace trackassoc::h5
