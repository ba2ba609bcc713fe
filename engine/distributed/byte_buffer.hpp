// The byte format of what ranks send each other (docs/design.md §8): a flat little-endian copy of plain
// values, strings and vectors, written and read in the same order by the same binary. No schema
// and no versioning: every rank of one job runs the same executable, so both ends agree.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace trackassoc::distributed {

using Bytes = std::vector<uint8_t>;

class ByteWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void put(const std::string& s) {
    put<uint64_t>(s.size());
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const std::vector<T>& v) {
    put<uint64_t>(v.size());
    const auto* p = reinterpret_cast<const uint8_t*>(v.data());
    bytes_.insert(bytes_.end(), p, p + v.size() * sizeof(T));
  }
  Bytes& bytes() { return bytes_; }
  Bytes take() { return std::move(bytes_); }

 private:
  Bytes bytes_;
};

// Reads what a ByteWriter wrote; a short buffer is an internal error (a bug, never user input).
class ByteReader {
 public:
  explicit ByteReader(const Bytes& bytes) : data_(bytes.data()), size_(bytes.size()) {}
  ByteReader(const uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  requires std::is_trivially_copyable_v<T> T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  std::string get_string() {
    const auto n = get<uint64_t>();
    const auto* p = take(n);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<uint64_t>();
    if (n > remaining() / sizeof(T))
      throw std::runtime_error("distributed message shorter than its content (a bug)");
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
    return v;
  }
  bool done() const { return pos_ == size_; }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const uint8_t* take(std::size_t n) {
    if (n > size_ - pos_) throw std::runtime_error("distributed message shorter than its content (a bug)");
    const uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  const uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

}  // namespace trackassoc::distributed
