// Options declared once (Stone Soup's `Property(default=..., doc=...)`): each field of an
// XxxOptions struct that a user may set in JSON is one OptionField, with its key, the member it
// sets, its range and its documentation; the default is the struct's own initializer (or a
// preset's value). From the one declaration come
//   - read():  JSON → struct, with the type checks ("solver 'X' options: 'key' must be a number",
//              "... must be an integer", "... = 5e9 is out of range for the field (...)", "... must
//              be true or false", "... must be a string") and the unknown-key error with its "did you
//              mean" (unknown_name_message, engine/solvers/solver_registry.hpp);
//   - write(): struct → JSON, the /associations/<name>/ "options" attribute;
//   - help():  one line per field (key, default, range, doc) for --help style listings.
// Enum fields read and write their names through kernels/core/enum_names.hpp.
//
// The range of a field is documentation here; the field's own range is enforced by the struct's
// validate() (docs/design.md §2), which the callers run after read(). read() checks only what the member's
// type can hold (an int32 count of 5e9, a float weight of 1e300), as read_option_number always has.
//
//   const OptionFields<LocalSearchOptions> kFields{{
//       field("max_rounds", &LocalSearchOptions::max_rounds, ">= 1", "rounds of the three moves")}};
//   LocalSearchOptions o;             // the defaults
//   kFields.read(json, o, "lr+ls");   // throws InputError naming the solver and the key
//   o.validate();
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/core/enum_names.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

// Whether `v` lies in the range of T (for float: finite and within ±max).
template <class T, class V>
bool in_limits(V v) {
  if constexpr (std::is_floating_point_v<V>) {
    if (!std::isfinite(v)) return false;
    if constexpr (std::is_integral_v<T>)
      return v >= static_cast<V>(std::numeric_limits<T>::lowest()) &&
             v <= static_cast<V>(std::numeric_limits<T>::max());
    else
      return v >= -static_cast<V>(std::numeric_limits<T>::max()) &&
             v <= static_cast<V>(std::numeric_limits<T>::max());
  } else if constexpr (std::is_floating_point_v<T>) {
    return true;
  } else {
    return std::in_range<T>(v);
  }
}

// Reads the JSON number `v` of option `key` into `target`; a wrong type, or a value the field cannot
// hold, is an InputError naming solver and key.
template <class T>
void read_number_value(const nlohmann::json& v, const std::string& key, T& target,
                       const std::string& solver) {
  if (!v.is_number()) throw InputError("solver '" + solver + "' options: '" + key + "' must be a number");
  if constexpr (std::is_integral_v<T>) {
    if (!v.is_number_integer())
      throw InputError("solver '" + solver + "' options: '" + key + "' must be an integer");
  }
  // A value the field cannot hold is an input error, never a wrapped integer or an inf float.
  const bool fits = v.is_number_integer() ? (v.is_number_unsigned() ? in_limits<T>(v.template get<uint64_t>())
                                                                    : in_limits<T>(v.template get<int64_t>()))
                                          : in_limits<T>(v.template get<double>());
  if (!fits) {
    std::ostringstream range;
    range << std::numeric_limits<T>::lowest() << " to " << std::numeric_limits<T>::max();
    throw InputError("solver '" + solver + "' options: '" + key + "' = " + v.dump() +
                     " is out of range for the field (" + range.str() + ")");
  }
  target = v.get<T>();
}

// Reads an optional number (absent or null options: `target` unchanged).
template <class T>
void read_option_number(const nlohmann::json& o, const char* key, T& target, const std::string& solver) {
  if (o.is_null() || !o.contains(key)) return;
  read_number_value(o.at(key), key, target, solver);
}

// Throws InputError("solver '<solver>' options: unknown key '<key>' (did you mean ...); known keys: ...").
[[noreturn]] void throw_unknown_option_key(const std::string& solver, const std::string& key,
                                           const std::vector<std::string>& known);

// A chain of member pointers, o.*a.*b...: path(&FuzzyPipelineOptions::fuzzy, &FuzzyAssociationOptions::gate).
template <class... P>
struct MemberPath {
  std::tuple<P...> members;
  template <class O>
  decltype(auto) operator()(O& o) const {
    return std::apply([&o](auto... m) -> decltype(auto) { return (o.*....*m); }, members);
  }
};
template <class... P>
MemberPath<P...> path(P... members) {
  return {{members...}};
}

template <class O>
struct OptionField {
  std::string key;
  std::string range;  // documentation (enforced by O::validate()); enums: their names
  std::string doc;
  // Reads `value` into `o`; `key` is the key as the user sees it (with a parent's "smoother.").
  std::function<void(O& o, const nlohmann::json& value, const std::string& key, const std::string& solver)>
      read;
  // The value written to the options attribute; nullopt: not written for this `o`.
  std::function<std::optional<nlohmann::json>(const O& o)> write;
};

namespace option_detail {

template <class T>
concept NamedEnum = std::is_enum_v<T> && requires(T e) {
  enum_names(e);
};

template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};

[[noreturn]] inline void type_error(const std::string& solver, const std::string& key, const char* expected) {
  throw InputError("solver '" + solver + "' options: '" + key + "' must be " + expected);
}

template <class T>
void read_value(T& target, const nlohmann::json& v, const std::string& key, const std::string& solver) {
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) type_error(solver, key, "true or false");
    target = v.get<bool>();
  } else if constexpr (std::is_arithmetic_v<T>) {
    read_number_value(v, key, target, solver);
  } else if constexpr (NamedEnum<T>) {
    if (!v.is_string()) type_error(solver, key, "a string");
    target = parse_enum<T>(v.get<std::string>(), key);
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) type_error(solver, key, "a string");
    target = v.get<std::string>();
  } else if constexpr (is_vector<T>::value) {
    if (!v.is_array()) type_error(solver, key, "an array of numbers");
    T out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      read_value(out[i], v[i], key + "[" + std::to_string(i) + "]", solver);
    target = std::move(out);
  } else {
    static_assert(sizeof(T) == 0, "no JSON reader for this option type");
  }
}

// nullopt for a non-finite number (JSON has none: an infinite time limit is the default, not written).
template <class T>
std::optional<nlohmann::json> write_value(const T& value) {
  if constexpr (NamedEnum<T>) {
    return enum_name(value);
  } else if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(value)) return std::nullopt;
    return value;
  } else {
    return value;
  }
}

template <class T>
std::string default_range() {
  if constexpr (NamedEnum<T>)
    return enum_name_list<T>();
  else if constexpr (std::is_same_v<T, bool>)
    return "true | false";
  else
    return "";
}

template <class M>
struct member_owner;
template <class C, class T>
struct member_owner<T C::*> {
  using type = C;
};
template <class First, class... Rest>
struct member_owner<MemberPath<First, Rest...>> {
  using type = typename member_owner<First>::type;
};

template <class A>
auto as_path(A a) {
  if constexpr (std::is_member_object_pointer_v<A>)
    return path(a);
  else
    return a;
}

}  // namespace option_detail

// A field set by `member` (a member pointer or a path(...)), of type bool, a number, a named enum,
// std::string or a vector of numbers.
template <class A, class O = typename option_detail::member_owner<A>::type>
OptionField<O> field(std::string key, A member, std::string range, std::string doc) {
  const auto at = option_detail::as_path(member);
  using T = std::remove_cvref_t<decltype(at(std::declval<O&>()))>;
  if (range.empty()) range = option_detail::default_range<T>();
  return {std::move(key), std::move(range), std::move(doc),
          [at](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
            option_detail::read_value(at(o), v, key, solver);
          },
          [at](const O& o) -> std::optional<nlohmann::json> { return option_detail::write_value(at(o)); }};
}

template <class O>
class OptionFields {
 public:
  OptionFields(std::vector<OptionField<O>> fields) : fields_(std::move(fields)) {}

  const std::vector<OptionField<O>>& fields() const { return fields_; }

  // The keys in declaration order (the order of the "known keys" in the unknown-key error).
  std::vector<std::string> keys(const std::string& prefix = "") const {
    std::vector<std::string> k;
    for (const auto& f : fields_) k.push_back(prefix + f.key);
    return k;
  }

  // Reads every key of `options` into `o`, in the JSON object's key order; null reads nothing.
  // An unknown key, a wrong type or a value the member cannot hold is an InputError starting with
  // "solver '<solver>' options: "; `prefix` names a parent object ("smoother.").
  void read(const nlohmann::json& options, O& o, const std::string& solver,
            const std::string& prefix = "") const {
    if (options.is_null()) return;
    if (!options.is_object()) {
      if (prefix.empty()) throw InputError("solver '" + solver + "' options: expected a JSON object");
      throw InputError("solver '" + solver + "' options: '" + prefix.substr(0, prefix.size() - 1) +
                       "' must be a JSON object");
    }
    for (auto it = options.begin(); it != options.end(); ++it) {
      const OptionField<O>* f = find(it.key());
      if (!f) throw_unknown_option_key(solver, prefix + it.key(), keys(prefix));
      try {
        f->read(o, it.value(), prefix + it.key(), solver);
      } catch (const InputError& e) {
        const std::string msg = e.what();
        if (msg.rfind("solver '", 0) == 0) throw;
        throw InputError("solver '" + solver + "' options: " + msg);
      }
    }
  }

  // The fields of `o` as a JSON object (keys sorted, as nlohmann::json keeps them).
  nlohmann::json write(const O& o) const {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& f : fields_)
      if (auto v = f.write(o)) j[f.key] = std::move(*v);
    return j;
  }

  // One line per field: key, its value in `defaults` ("-" when not written), range and doc.
  std::string help(const O& defaults, const std::string& indent = "  ") const {
    std::size_t wk = 3, wd = 7, wr = 5;
    std::vector<std::string> values;
    for (const auto& f : fields_) {
      const auto v = f.write(defaults);
      values.push_back(v ? v->dump() : "-");
      wk = std::max(wk, f.key.size());
      wd = std::max(wd, values.back().size());
      wr = std::max(wr, f.range.size());
    }
    auto pad = [](const std::string& s, std::size_t w) { return s + std::string(w - s.size() + 2, ' '); };
    std::string out = indent + pad("key", wk) + pad("default", wd) + pad("range", wr) + "doc\n";
    for (std::size_t i = 0; i < fields_.size(); ++i)
      out += indent + pad(fields_[i].key, wk) + pad(values[i], wd) + pad(fields_[i].range, wr) +
             fields_[i].doc + "\n";
    return out;
  }

 private:
  const OptionField<O>* find(const std::string& key) const {
    for (const auto& f : fields_)
      if (f.key == key) return &f;
    return nullptr;
  }
  std::vector<OptionField<O>> fields_;
};

// A nested JSON object read by `sub` (a static: it is held by reference) into the member `member` (smoother:
// {gains, alpha, ...}).
template <class A, class Sub, class O = typename option_detail::member_owner<A>::type>
OptionField<O> object_field(std::string key, A member, const OptionFields<Sub>& sub, std::string doc) {
  const auto at = option_detail::as_path(member);
  return {key,
          "{" +
              [&] {
                std::string k;
                for (const auto& s : sub.keys()) k += (k.empty() ? "" : ", ") + s;
                return k;
              }() +
              "}",
          std::move(doc),
          [at, &sub](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
            if (!v.is_object()) option_detail::type_error(solver, key, "a JSON object");
            sub.read(v, at(o), solver, key + ".");
          },
          [at, &sub](const O& o) -> std::optional<nlohmann::json> { return sub.write(at(o)); }};
}

}  // namespace trackassoc
