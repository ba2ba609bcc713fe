// A small RAII layer over the HDF5 C API (1.10), just what the schema v1 reader and writer need.
//
// - Every hid_t lives in a move-only Handle that closes it with the right H5?close.
// - Every return code is checked; a failure throws InputError "FILE: /group/object: what", so the
//   CLI prints one line (the library's own error stack printing is switched off).
// - Groups and datasets are created without modification times (H5Pset_obj_track_times false), so
//   the same content gives a bit-identical file (docs/design.md §7 Reproducibility).
// - Files use the HDF5 1.8 format (checksummed superblock and object headers), so that corruption
//   is detected rather than decoded; strings are variable-length UTF-8, h5py's `str` (see
//   write_attribute for why that is safe with the forked reader).
// - Readers check the dtype class (a string where numbers are expected is an error), accept any
//   integer or float width and convert to the memory type, and check rank and shape.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace trackassoc::h5 {

// "3x4", or "a scalar": a dataset shape for error messages.
std::string shape_text(const std::vector<hsize_t>& dims);

// Switches off HDF5's automatic error stack printing (once per process).
void silence_library_errors();

class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { close(); }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  herr_t close();  // returns the closer's status; idempotent

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

// Which element types a numeric reader accepts from the file.
enum class NumberClass { kInteger, kIntegerOrFloat };

class File;

// A group (the root included) of an open file. Names in messages are full paths ("/tracks/cov").
class Group {
 public:
  Group(const std::string& file_path, Handle handle, std::string path)
      : file_path_(file_path), handle_(std::move(handle)), path_(std::move(path)) {}

  const std::string& path() const { return path_; }
  std::string child_path(const std::string& name) const {
    return path_ == "/" ? "/" + name : path_ + "/" + name;
  }
  hid_t id() const { return handle_.get(); }

  // Creation. `track_order` keeps the children in creation order (for /associations, /metrics).
  Group create_group(const std::string& name, bool track_order = false) const;
  void write_attribute(const std::string& name, const std::string& value) const;  // UTF-8, variable length
  void write_attribute(const std::string& name, double value) const;
  void write_attribute(const std::string& name, int32_t value) const;
  void write_attribute(const std::string& name, uint64_t value) const;
  // Row-major, of rank dims.size() (1-D and 2-D in schema v1; any rank works). dims may contain 0.
  void write_dataset(const std::string& name, std::span<const int32_t> data, std::vector<hsize_t> dims) const;
  void write_dataset(const std::string& name, std::span<const double> data, std::vector<hsize_t> dims) const;
  void write_dataset(const std::string& name, std::span<const float> data, std::vector<hsize_t> dims) const;
  void write_dataset(const std::string& name, std::span<const int64_t> data, std::vector<hsize_t> dims) const;
  void write_dataset(const std::string& name, std::span<const uint8_t> data, std::vector<hsize_t> dims) const;

  // Reading.
  bool has(const std::string& name) const;  // a link of that name exists
  bool is_group(const std::string& name) const;
  bool has_attribute(const std::string& name) const;
  Group open_group(const std::string& name) const;  // throws "missing group" when absent
  std::vector<std::string> children() const;        // creation order if tracked, else by name
  std::string read_string_attribute(const std::string& name) const;
  double read_double_attribute(const std::string& name) const;  // integer or float attribute
  int64_t read_integer_attribute(const std::string& name) const;
  uint64_t read_unsigned_attribute(const std::string& name) const;
  // Shape of a dataset, without reading it.
  std::vector<hsize_t> dataset_shape(const std::string& name) const;
  // The rows of a table stored as one dataset per column: the first dimension of columns[0], after
  // checking from the shapes alone (nothing is read yet) that every other column present has as
  // many rows, and that reading them all (8 bytes per element, the largest matrix twice: read by
  // rows, laid out by columns) fits the memory budget beside what the process holds.
  std::size_t table_rows(std::initializer_list<const char*> columns) const;
  // Reads a whole numeric dataset, converting to the memory type. `dims` receives the shape;
  // the rank must be `rank` (1 or 2).
  std::vector<double> read_doubles(const std::string& name, int rank, std::vector<hsize_t>& dims) const;
  std::vector<float> read_floats(const std::string& name, int rank, std::vector<hsize_t>& dims) const;
  std::vector<int64_t> read_integers(const std::string& name, int rank, std::vector<hsize_t>& dims) const;

  [[noreturn]] void fail(const std::string& object, const std::string& what) const;

 private:
  void write_numeric(const std::string& name, hid_t file_type, hid_t mem_type, const void* data,
                     std::vector<hsize_t> dims, std::size_t count) const;
  Handle open_numeric_dataset(const std::string& name, NumberClass accepted, int rank,
                              std::vector<hsize_t>& dims, std::size_t& count) const;
  template <typename T>
  std::vector<T> read_typed(const std::string& name, NumberClass accepted, hid_t mem_type, int rank,
                            std::vector<hsize_t>& dims) const;
  void require_stored(const Handle& set, const std::string& name, const std::vector<hsize_t>& dims,
                      std::size_t count) const;
  Handle open_numeric_attribute(const std::string& name, NumberClass accepted) const;

  std::string file_path_;
  Handle handle_;
  std::string path_;
};

class File {
 public:
  // Creates (truncates) `path` for writing.
  static File create(const std::string& path);
  // Opens an existing file read-only; checks existence and H5Fis_hdf5 first so that an empty,
  // truncated or foreign file gives a clear InputError.
  static File open_read_only(const std::string& path);

  const std::string& path() const { return path_; }
  Group root() const;
  // Flushes and closes; throws when the library reports a failure (e.g. disk full).
  void close();

  File(File&&) = default;

 private:
  File(std::string path, Handle handle) : path_(std::move(path)), handle_(std::move(handle)) {}
  std::string path_;
  Handle handle_;
};

// Checks that the root of `path` has the string attribute format = `format` and the integer
// attribute schema_version = `version`; otherwise an InputError naming the file and saying that it
// is not a `what` (e.g. "Siamese model file").
void require_format(const Group& root, const std::string& path, const std::string& format, int64_t version,
                    const std::string& what);

// Largest number of elements a reader allocates for one dataset (2^28: 2 GiB of doubles). A
// corrupt header claiming more is reported instead of exhausting memory.
inline constexpr std::size_t kMaxDatasetElements = std::size_t{1} << 28;

}  // namespace trackassoc::h5
