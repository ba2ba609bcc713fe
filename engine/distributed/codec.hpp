// Codecs declared once (as engine/solvers/option_fields.hpp declares options): what ranks send each
// other is a struct, and its byte form is the list of its fields, never a hand-written pair of
// encode and decode functions that must be kept in step.
//
//   // beside Seed004Row (found by argument-dependent lookup):
//   constexpr auto wire_codec(std::type_identity<Seed004Row>) {
//     return distributed::codec<Seed004Row>("seed004 row", &Seed004Row::scenario, &Seed004Row::targets,
//                                           &Seed004Row::converged);
//   }
//   const Bytes b = codec_of<Seed004Row>().to_bytes(row);     // encode() generated from the list
//   Seed004Row r = codec_of<Seed004Row>().from_bytes(b);      // decode(): the same list, in order
//
// A field travels by its type (engine/distributed/byte_buffer.hpp's flat little-endian form):
//   * a trivially copyable value (numbers, enums, std::array of numbers, plain structs): its bytes;
//   * bool: one byte, 0 or 1;
//   * std::string, std::vector<T>: a uint64 count, then the elements (raw bytes when T is
//     trivially copyable);
//   * std::array<T, N> of other T: its N elements;
//   * a type with a wire_codec: its declared fields (nested structs), or, for a type
//     whose members are not its wire form (a CSR matrix that travels as its gated entries), a
//     conversion to a declared wire struct and back (converted_codec).
// Every rank of one job runs the same binary, so both ends agree (no schema, no versioning). A
// buffer shorter or longer than its declared fields is refused with an error naming the codec (an
// internal error: the bytes come from another rank, never from a user).
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/distributed/byte_buffer.hpp"

namespace trackassoc::distributed {

// A type is declared by a constexpr function wire_codec(std::type_identity<T>) in its own
// namespace (an anonymous one too), returning codec<T>(...) or converted_codec<T, W>(...).
template <class T>
concept Declared = requires {
  wire_codec(std::type_identity<T>{});
};

template <Declared T>
const auto& codec_of() {
  static constexpr auto c = wire_codec(std::type_identity<T>{});
  return c;
}

namespace codec_detail {

template <class T>
struct is_vector : std::false_type {};
template <class T, class A>
struct is_vector<std::vector<T, A>> : std::true_type {};
template <class T>
struct is_array : std::false_type {};
template <class T, std::size_t N>
struct is_array<std::array<T, N>> : std::true_type {};

template <class T>
void put_value(ByteWriter& w, const T& x);
template <class T>
void get_value(ByteReader& r, T& x);

template <class T>
void put_value(ByteWriter& w, const T& x) {
  if constexpr (Declared<T>) {
    codec_of<T>().encode(w, x);
  } else if constexpr (std::is_same_v<T, bool>) {
    w.put<uint8_t>(x ? 1 : 0);
  } else if constexpr (std::is_same_v<T, std::string>) {
    w.put(x);
  } else if constexpr (is_vector<T>::value) {
    using E = typename T::value_type;
    static_assert(!std::is_same_v<E, bool>, "std::vector<bool> has no contiguous storage; use uint8_t");
    if constexpr (std::is_trivially_copyable_v<E> && !Declared<E>) {
      w.put(x);
    } else {
      w.put<uint64_t>(x.size());
      for (const auto& e : x) put_value(w, e);
    }
  } else if constexpr (is_array<T>::value && !std::is_trivially_copyable_v<T>) {
    for (const auto& e : x) put_value(w, e);
  } else {
    static_assert(std::is_trivially_copyable_v<T>, "declare a wire_codec for this type");
    w.put(x);
  }
}

template <class T>
void get_value(ByteReader& r, T& x) {
  if constexpr (Declared<T>) {
    x = codec_of<T>().decode(r);
  } else if constexpr (std::is_same_v<T, bool>) {
    const auto b = r.get<uint8_t>();
    if (b > 1) throw std::runtime_error("distributed message: a bool field holds " + std::to_string(b));
    x = b != 0;
  } else if constexpr (std::is_same_v<T, std::string>) {
    x = r.get_string();
  } else if constexpr (is_vector<T>::value) {
    using E = typename T::value_type;
    if constexpr (std::is_trivially_copyable_v<E> && !Declared<E>) {
      x = r.get_vector<E>();
    } else {
      const auto n = r.get<uint64_t>();
      x.clear();  // element by element: a corrupt count fails on the short buffer, not in an allocation
      for (uint64_t k = 0; k < n; ++k) get_value(r, x.emplace_back());
    }
  } else if constexpr (is_array<T>::value && !std::is_trivially_copyable_v<T>) {
    for (auto& e : x) get_value(r, e);
  } else {
    x = r.get<T>();
  }
}

// Runs decode over all of `bytes`; a short or long buffer is an error naming `name`.
template <class T, class Decode>
T decode_whole(const char* name, const Bytes& bytes, Decode decode) {
  ByteReader r(bytes);
  T x;
  try {
    x = decode(r);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("distributed message '") + name + "' (" +
                             std::to_string(bytes.size()) +
                             " bytes) does not hold its declared fields: " + e.what());
  }
  if (!r.done())
    throw std::runtime_error(std::string("distributed message '") + name + "' (" +
                             std::to_string(bytes.size()) + " bytes) is longer than its declared fields: " +
                             std::to_string(r.remaining()) + " bytes left over (a bug)");
  return x;
}

}  // namespace codec_detail

// What every codec offers from its encode(ByteWriter&, const T&) and decode(ByteReader&).
template <class Derived, class T>
class CodecBase {
 public:
  constexpr explicit CodecBase(const char* name) : name_(name) {}
  const char* name() const { return name_; }
  Bytes to_bytes(const T& x) const {
    ByteWriter w;
    self().encode(w, x);
    return w.take();
  }
  // All of `bytes` as one T; a buffer shorter or longer than the fields is refused, naming the codec.
  T from_bytes(const Bytes& bytes) const {
    return codec_detail::decode_whole<T>(name_, bytes, [this](ByteReader& r) { return self().decode(r); });
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  const char* name_;
};

// The codec of T made of the fields `members`, written and read in that order.
template <class T, class... M>
class Codec : public CodecBase<Codec<T, M...>, T> {
 public:
  constexpr Codec(const char* name, M T::*... members) : CodecBase<Codec, T>(name), members_(members...) {}
  static constexpr std::size_t fields() { return sizeof...(M); }
  void encode(ByteWriter& w, const T& x) const {
    std::apply([&](auto... m) { (codec_detail::put_value(w, x.*m), ...); }, members_);
  }
  T decode(ByteReader& r) const {
    T x{};
    std::apply([&](auto... m) { (codec_detail::get_value(r, x.*m), ...); }, members_);
    return x;
  }

 private:
  std::tuple<M T::*...> members_;
};

template <class T, class... M>
constexpr Codec<T, M...> codec(const char* name, M T::*... members) {
  return Codec<T, M...>(name, members...);
}

// A type that travels as another, declared one: to(x) gives its wire form W, from(w) rebuilds it
// (and may refuse a W that breaks T's invariants with a std::runtime_error).
template <class T, class W>
class ConvertedCodec : public CodecBase<ConvertedCodec<T, W>, T> {
 public:
  constexpr ConvertedCodec(const char* name, W (*to)(const T&), T (*from)(const W&))
      : CodecBase<ConvertedCodec, T>(name), to_(to), from_(from) {}
  void encode(ByteWriter& w, const T& x) const { codec_of<W>().encode(w, to_(x)); }
  T decode(ByteReader& r) const { return from_(codec_of<W>().decode(r)); }

 private:
  W (*to_)(const T&);
  T (*from_)(const W&);
};

template <class T, class W>
constexpr ConvertedCodec<T, W> converted_codec(const char* name, W (*to)(const T&), T (*from)(const W&)) {
  return ConvertedCodec<T, W>(name, to, from);
}

}  // namespace trackassoc::distributed
