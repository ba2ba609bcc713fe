// A minimal RAII layer over the HDF5 1.10 C API for the Siamese model and data set files.
//
// Every HDF5 call is checked; a failure throws InputError naming the file and the object. HDF5's
// own error stack printing is switched off (we report instead). This is local to the Siamese files
// because io/hdf5_wrapper.hpp (branch io) had not landed on main when they were written, and it
// writes no int64/uint8 datasets, which the seed 003 data set uses. Its own namespace keeps it
// apart from trackassoc::h5. TODO: port the Siamese files onto io/hdf5_wrapper.hpp.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace trackassoc::siamese_h5 {

// Owns one hid_t and closes it with the matching H5*close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  hid_t release() {
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// A file being written or read; `path` is used in every error message.
class File {
 public:
  static File create(const std::string& path);     // truncates; callers write to a .tmp path
  static File open_read(const std::string& path);  // clear error for missing / non-HDF5 files
  const std::string& path() const { return path_; }
  hid_t id() const { return file_.get(); }
  void close();  // flushes and closes, checking for errors

  // Groups are created with their parents ("a/b/c").
  void create_group(const std::string& name);
  bool exists(const std::string& name) const;

  void write_attribute(const std::string& object, const std::string& name, const std::string& value);
  void write_attribute(const std::string& object, const std::string& name, int64_t value);
  void write_attribute(const std::string& object, const std::string& name, double value);
  std::string read_string_attribute(const std::string& object, const std::string& name) const;
  int64_t read_int_attribute(const std::string& object, const std::string& name) const;
  double read_double_attribute(const std::string& object, const std::string& name) const;

  // Datasets of rank 1 (cols == 0) or rank 2 (rows × cols, row-major), compressed when large.
  void write(const std::string& name, const float* data, hsize_t rows, hsize_t cols = 0);
  void write(const std::string& name, const double* data, hsize_t rows, hsize_t cols = 0);
  void write(const std::string& name, const int32_t* data, hsize_t rows, hsize_t cols = 0);
  void write(const std::string& name, const int64_t* data, hsize_t rows, hsize_t cols = 0);
  void write(const std::string& name, const uint8_t* data, hsize_t rows, hsize_t cols = 0);

  // Shape of a dataset (rank 1: {n}; rank 2: {rows, cols}); error when missing.
  std::vector<hsize_t> shape(const std::string& name) const;
  // Reads a whole dataset, checking its type class (float / integer) and, when given, its shape.
  std::vector<float> read_float(const std::string& name,
                                const std::vector<hsize_t>& expected_shape = {}) const;
  std::vector<double> read_double(const std::string& name,
                                  const std::vector<hsize_t>& expected_shape = {}) const;
  std::vector<int32_t> read_int32(const std::string& name,
                                  const std::vector<hsize_t>& expected_shape = {}) const;
  std::vector<int64_t> read_int64(const std::string& name,
                                  const std::vector<hsize_t>& expected_shape = {}) const;
  std::vector<uint8_t> read_uint8(const std::string& name,
                                  const std::vector<hsize_t>& expected_shape = {}) const;

 private:
  std::string path_;
  Handle file_;
  void write_any(const std::string& name, hid_t mem_type, hid_t file_type, const void* data, hsize_t rows,
                 hsize_t cols);
  void read_any(const std::string& name, hid_t mem_type, bool want_float, void* data, std::size_t count,
                const std::vector<hsize_t>& expected_shape) const;
  template <class T>
  std::vector<T> read_vector(const std::string& name, hid_t mem_type, bool want_float,
                             const std::vector<hsize_t>& expected_shape) const;
};

}  // namespace trackassoc::siamese_h5
