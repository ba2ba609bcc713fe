// The reader of one scenario JSON object (io/scenario_json.hpp), shared by the scenario's parts
// (io/scenario_json.cpp, io/scenario_json_widearea.cpp). Internal to io/.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/scenario.hpp"

namespace trackassoc::scenario_json_detail {

using json = nlohmann::json;

inline constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// One JSON object being read: every key must be consumed, so a misspelt key is reported.
class Reader {
 public:
  Reader(const json& object, std::string path, const std::string& source)
      : object_(object), path_(std::move(path)), source_(source) {
    if (!object_.is_object()) fail(path_, "expected an object", object_);
  }
  ~Reader() = default;

  [[noreturn]] void fail(const std::string& path, const std::string& expected, const json& found) const {
    std::string shown = found.dump();
    if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
    throw InputError(source_ + ": " + (path.empty() ? "(top level)" : path) + ": " + expected + ", found " +
                     std::string(found.type_name()) + " " + shown);
  }
  std::string key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  const json* get(const std::string& key) {
    auto it = object_.find(key);
    if (it == object_.end()) return nullptr;
    seen_.insert(key);
    return &*it;
  }

  // A finite number, optionally bounded; `rule` describes the bound for the message.
  void number(const std::string& key, double& out, bool (*ok)(double) = nullptr, const char* rule = "") {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number()) fail(key_path(key), std::string("expected a number") + rule, *v);
    const double d = v->get<double>();
    if (!std::isfinite(d) || (ok && !ok(d)))
      fail(key_path(key), std::string("expected a finite number") + rule, *v);
    out = d;
  }
  // An angle given either as KEY_deg (degrees) or KEY_rad (radians), stored in radians.
  // `suffix` is "" for angles and "_s" for angular rates.
  void angle(const std::string& key, const std::string& suffix, double& out, bool (*ok)(double),
             const char* rule) {
    const std::string deg = key + "_deg" + suffix, rad = key + "_rad" + suffix;
    const bool has_deg = object_.contains(deg), has_rad = object_.contains(rad);
    if (has_deg && has_rad)
      throw InputError(source_ + ": " + key_path(deg) + ": give either " + deg + " or " + rad + ", not both");
    double value = 0.0;
    if (has_deg) {
      number(deg, value, nullptr, "");
      value *= kDegToRad;
    } else if (has_rad) {
      number(rad, value, nullptr, "");
    } else {
      return;
    }
    if (ok && !ok(value))
      fail(key_path(has_deg ? deg : rad), std::string("expected a number") + rule,
           object_[has_deg ? deg : rad]);
    out = value;
  }
  template <typename Int>
  void integer(const std::string& key, Int& out, int64_t min_value, int64_t max_value) {
    const json* v = get(key);
    if (!v) return;
    const std::string range = " in [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "]";
    if (!v->is_number_integer()) fail(key_path(key), "expected an integer" + range, *v);
    if (v->is_number_unsigned()) {
      const uint64_t u = v->get<uint64_t>();
      if (u > static_cast<uint64_t>(max_value) || static_cast<int64_t>(u) < min_value)
        fail(key_path(key), "expected an integer" + range, *v);
      out = static_cast<Int>(u);
      return;
    }
    const int64_t i = v->get<int64_t>();
    if (i < min_value || i > max_value) fail(key_path(key), "expected an integer" + range, *v);
    out = static_cast<Int>(i);
  }
  void seed(const std::string& key, uint64_t& out) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number_unsigned()) fail(key_path(key), "expected a non-negative integer", *v);
    out = v->get<uint64_t>();
  }
  void string(const std::string& key, std::string& out) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_string()) fail(key_path(key), "expected a string", *v);
    out = v->get<std::string>();
  }
  // [x, y] or [x, y, z]: a missing z is 0.
  void vector3(const std::string& key, std::array<double, 3>& out) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_array() || v->size() < 2 || v->size() > 3)
      fail(key_path(key), "expected an array of 2 or 3 numbers", *v);
    std::array<double, 3> r{0, 0, 0};
    for (std::size_t i = 0; i < v->size(); ++i) {
      const json& e = (*v)[i];
      if (!e.is_number() || !std::isfinite(e.get<double>()))
        fail(key_path(key) + "[" + std::to_string(i) + "]", "expected a finite number", e);
      r[i] = e.get<double>();
    }
    out = r;
  }
  const json* array(const std::string& key) {
    const json* v = get(key);
    if (v && !v->is_array()) fail(key_path(key), "expected an array", *v);
    return v;
  }
  // Refuses `key` = value below `other` = min (two bounds of one range).
  void not_below(const std::string& key, double value, const std::string& other, double min) const {
    if (value < min) throw InputError(source_ + ": " + key_path(key) + ": expected " + key + " >= " + other);
  }
  // Call last: every key of the object must have been read.
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it)
      if (!seen_.count(it.key()))
        throw InputError(source_ + ": " + key_path(it.key()) +
                         ": unknown key (see io/scenario_json.hpp for the format)");
  }
  const std::string& path() const { return path_; }
  const std::string& source() const { return source_; }

 private:
  const json& object_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> seen_;
};

inline bool positive(double v) { return v > 0; }
inline bool non_negative(double v) { return v >= 0; }
inline bool probability(double v) { return v > 0 && v <= 1; }

inline bool unit_interval(double v) { return v >= 0 && v <= 1; }

// The "wide_area" block (io/scenario_json_widearea.cpp).
void read_wide_area(Reader& r, WideAreaSpec& w);
nlohmann::ordered_json wide_area_json(const WideAreaSpec& w);

}  // namespace trackassoc::scenario_json_detail
