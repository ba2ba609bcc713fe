// RAII layer over the HDF5 C API (see siamese_hdf5.hpp).
#include "io/siamese_hdf5.hpp"

#include <filesystem>

#include "kernels/error.hpp"

namespace trackassoc::siamese_h5 {
namespace {

void silence_hdf5() {
  // HDF5 prints its error stack by default; we throw our own message instead.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

std::string shape_text(const std::vector<hsize_t>& s) {
  std::string t = "(";
  for (std::size_t k = 0; k < s.size(); ++k) t += (k ? ", " : "") + std::to_string(s[k]);
  return t + ")";
}

}  // namespace

File File::create(const std::string& path) {
  silence_hdf5();
  File f;
  f.path_ = path;
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) throw InputError(path + ": cannot create HDF5 file");
  f.file_ = Handle(id, H5Fclose);
  return f;
}

File File::open_read(const std::string& path) {
  silence_hdf5();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path + ": not an HDF5 file (or truncated/corrupted)");
  File f;
  f.path_ = path;
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw InputError(path + ": cannot open HDF5 file (truncated or corrupted?)");
  f.file_ = Handle(id, H5Fclose);
  return f;
}

void File::close() {
  if (file_.get() < 0) return;
  if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) throw InputError(path_ + ": cannot flush HDF5 file");
  if (H5Fclose(file_.release()) < 0) throw InputError(path_ + ": cannot close HDF5 file");
}

void File::create_group(const std::string& name) {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (lcpl.get() < 0 || H5Pset_create_intermediate_group(lcpl.get(), 1) < 0)
    throw InputError(path_ + ": cannot set up group creation");
  Handle g(H5Gcreate2(file_.get(), name.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (g.get() < 0) throw InputError(path_ + ": cannot create group " + name);
}

bool File::exists(const std::string& name) const {
  // Check each component, since H5Lexists fails on a missing intermediate group.
  std::string partial;
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    const std::size_t next = name.find('/', pos + 1);
    partial = name.substr(0, next);
    if (!partial.empty() && partial != "/" && H5Lexists(file_.get(), partial.c_str(), H5P_DEFAULT) <= 0)
      return false;
    pos = next;
  }
  return true;
}

static Handle open_object(const File& f, const std::string& object) {
  const hid_t id = H5Oopen(f.id(), object.c_str(), H5P_DEFAULT);
  if (id < 0) throw InputError(f.path() + ": missing object " + object);
  return Handle(id, H5Oclose);
}

static void write_attr(const File& f, const std::string& object, const std::string& name, hid_t type,
                       const void* value) {
  Handle obj = open_object(f, object);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle a(H5Acreate2(obj.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (a.get() < 0 || H5Awrite(a.get(), type, value) < 0)
    throw InputError(f.path() + ": cannot write attribute " + object + "@" + name);
}

void File::write_attribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (type.get() < 0 || H5Tset_size(type.get(), value.size() + 1) < 0 ||
      H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    throw InputError(path_ + ": cannot make string type for " + object + "@" + name);
  write_attr(*this, object, name, type.get(), value.c_str());
}

void File::write_attribute(const std::string& object, const std::string& name, int64_t value) {
  write_attr(*this, object, name, H5T_NATIVE_INT64, &value);
}

void File::write_attribute(const std::string& object, const std::string& name, double value) {
  write_attr(*this, object, name, H5T_NATIVE_DOUBLE, &value);
}

static Handle open_attr(const File& f, const std::string& object, const std::string& name, H5T_class_t want) {
  Handle obj = open_object(f, object);
  if (H5Aexists(obj.get(), name.c_str()) <= 0)
    throw InputError(f.path() + ": missing attribute " + object + "@" + name);
  Handle a(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (a.get() < 0) throw InputError(f.path() + ": cannot open attribute " + object + "@" + name);
  Handle type(H5Aget_type(a.get()), H5Tclose);
  if (type.get() < 0 || H5Tget_class(type.get()) != want)
    throw InputError(f.path() + ": attribute " + object + "@" + name + " has the wrong type");
  Handle space(H5Aget_space(a.get()), H5Sclose);
  if (space.get() < 0 || H5Sget_simple_extent_npoints(space.get()) != 1)
    throw InputError(f.path() + ": attribute " + object + "@" + name + " is not a scalar");
  return a;
}

std::string File::read_string_attribute(const std::string& object, const std::string& name) const {
  Handle a = open_attr(*this, object, name, H5T_STRING);
  Handle type(H5Aget_type(a.get()), H5Tclose);
  if (H5Tis_variable_str(type.get()) > 0) {
    char* s = nullptr;
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    if (H5Aread(a.get(), mem.get(), &s) < 0) throw InputError(path_ + ": cannot read " + object + "@" + name);
    std::string out = s ? s : "";
    H5free_memory(s);
    return out;
  }
  const std::size_t size = H5Tget_size(type.get());
  if (size == 0 || size > (std::size_t{1} << 26))
    throw InputError(path_ + ": bad string size for " + object + "@" + name);
  std::string buf(size, '\0');
  Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem.get(), size);
  H5Tset_cset(mem.get(), H5Tget_cset(type.get()));  // HDF5 will not convert between ASCII and UTF-8
  if (H5Aread(a.get(), mem.get(), buf.data()) < 0)
    throw InputError(path_ + ": cannot read " + object + "@" + name);
  buf.resize(buf.find('\0') == std::string::npos ? size : buf.find('\0'));
  return buf;
}

int64_t File::read_int_attribute(const std::string& object, const std::string& name) const {
  Handle a = open_attr(*this, object, name, H5T_INTEGER);
  int64_t v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_INT64, &v) < 0)
    throw InputError(path_ + ": cannot read " + object + "@" + name);
  return v;
}

double File::read_double_attribute(const std::string& object, const std::string& name) const {
  Handle a = open_attr(*this, object, name, H5T_FLOAT);
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0)
    throw InputError(path_ + ": cannot read " + object + "@" + name);
  return v;
}

void File::write_any(const std::string& name, hid_t mem_type, hid_t file_type, const void* data, hsize_t rows,
                     hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  const int rank = cols == 0 ? 1 : 2;
  Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (space.get() < 0 || dcpl.get() < 0 || lcpl.get() < 0 ||
      H5Pset_create_intermediate_group(lcpl.get(), 1) < 0)
    throw InputError(path_ + ": cannot set up dataset " + name);
  const hsize_t total = rank == 1 ? rows : rows * cols;
  if (total >= 4096) {  // chunk + deflate large datasets (h5py reads them transparently)
    hsize_t chunk[2] = {std::min<hsize_t>(rows, rank == 1 ? 65536 : std::max<hsize_t>(1, 65536 / cols)),
                        cols};
    if (H5Pset_chunk(dcpl.get(), rank, chunk) < 0 || H5Pset_deflate(dcpl.get(), 4) < 0)
      throw InputError(path_ + ": cannot set compression for " + name);
  }
  Handle ds(
      H5Dcreate2(file_.get(), name.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
      H5Dclose);
  if (ds.get() < 0) throw InputError(path_ + ": cannot create dataset " + name);
  if (total > 0 && H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw InputError(path_ + ": cannot write dataset " + name);
}

void File::write(const std::string& n, const float* d, hsize_t r, hsize_t c) {
  write_any(n, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, d, r, c);
}
void File::write(const std::string& n, const double* d, hsize_t r, hsize_t c) {
  write_any(n, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, d, r, c);
}
void File::write(const std::string& n, const int32_t* d, hsize_t r, hsize_t c) {
  write_any(n, H5T_NATIVE_INT32, H5T_STD_I32LE, d, r, c);
}
void File::write(const std::string& n, const int64_t* d, hsize_t r, hsize_t c) {
  write_any(n, H5T_NATIVE_INT64, H5T_STD_I64LE, d, r, c);
}
void File::write(const std::string& n, const uint8_t* d, hsize_t r, hsize_t c) {
  write_any(n, H5T_NATIVE_UINT8, H5T_STD_U8LE, d, r, c);
}

std::vector<hsize_t> File::shape(const std::string& name) const {
  if (!exists(name)) throw InputError(path_ + ": missing dataset " + name);
  Handle ds(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds.get() < 0) throw InputError(path_ + ": " + name + " is not a readable dataset");
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const int rank = space.get() < 0 ? -1 : H5Sget_simple_extent_ndims(space.get());
  if (rank < 1 || rank > 2)
    throw InputError(path_ + ": dataset " + name + " has rank " + std::to_string(rank) + ", expected 1 or 2");
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

void File::read_any(const std::string& name, hid_t mem_type, bool want_float, void* data, std::size_t count,
                    const std::vector<hsize_t>& expected_shape) const {
  Handle ds(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds.get() < 0) throw InputError(path_ + ": missing dataset " + name);
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  const H5T_class_t cls = type.get() < 0 ? H5T_NO_CLASS : H5Tget_class(type.get());
  if (cls != (want_float ? H5T_FLOAT : H5T_INTEGER))
    throw InputError(path_ + ": dataset " + name + " has the wrong type, expected " +
                     (want_float ? "floating point" : "integer"));
  if (count > 0 && H5Dread(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw InputError(path_ + ": cannot read dataset " + name + " (truncated or corrupted file?)");
  (void)expected_shape;
}

template <class T>
std::vector<T> File::read_vector(const std::string& name, hid_t mem_type, bool want_float,
                                 const std::vector<hsize_t>& expected_shape) const {
  const std::vector<hsize_t> dims = shape(name);
  if (!expected_shape.empty() && dims != expected_shape)
    throw InputError(path_ + ": dataset " + name + " has shape " + shape_text(dims) + ", expected " +
                     shape_text(expected_shape));
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  if (count > (hsize_t{1} << 34)) throw InputError(path_ + ": dataset " + name + " is implausibly large");
  std::vector<T> out(static_cast<std::size_t>(count));
  read_any(name, mem_type, want_float, out.data(), out.size(), expected_shape);
  return out;
}

std::vector<float> File::read_float(const std::string& n, const std::vector<hsize_t>& s) const {
  return read_vector<float>(n, H5T_NATIVE_FLOAT, true, s);
}
std::vector<double> File::read_double(const std::string& n, const std::vector<hsize_t>& s) const {
  return read_vector<double>(n, H5T_NATIVE_DOUBLE, true, s);
}
std::vector<int32_t> File::read_int32(const std::string& n, const std::vector<hsize_t>& s) const {
  return read_vector<int32_t>(n, H5T_NATIVE_INT32, false, s);
}
std::vector<int64_t> File::read_int64(const std::string& n, const std::vector<hsize_t>& s) const {
  return read_vector<int64_t>(n, H5T_NATIVE_INT64, false, s);
}
std::vector<uint8_t> File::read_uint8(const std::string& n, const std::vector<hsize_t>& s) const {
  return read_vector<uint8_t>(n, H5T_NATIVE_UINT8, false, s);
}

}  // namespace trackassoc::siamese_h5
