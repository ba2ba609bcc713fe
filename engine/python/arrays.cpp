#include "engine/python/arrays.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "io/csv_tracks.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::python {

namespace {

std::string dataset(const std::string& group, const std::string& column) {
  return "/" + group + "/" + column;
}

[[noreturn]] void fail(const std::string& group, const std::string& column, const std::string& what) {
  throw InputError(std::string(kArraysSource) + ": " + dataset(group, column) + ": " + what);
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

bool has_field(const py::handle& table, const char* key) {
  if (py::isinstance<py::dict>(table)) return table.cast<py::dict>().contains(key);
  if (py::isinstance<py::array>(table)) {
    const py::object names = table.cast<py::array>().dtype().attr("names");
    if (names.is_none()) return false;
    for (const auto& n : names)
      if (n.cast<std::string>() == key) return true;
    return false;
  }
  return py::hasattr(table, "__getitem__") && py::hasattr(table, "__contains__") &&
         table.attr("__contains__")(key).cast<bool>();
}

// The column `key` of a dict or structured array as an array (numpy.asarray), or a missing-column error.
py::array column(const py::handle& table, const std::string& group, const char* key) {
  if (!has_field(table, key)) fail(group, key, "expected this column, found none");
  return py::module_::import("numpy").attr("asarray")(table[py::str(key)]).cast<py::array>();
}

char dtype_kind(const py::array& a) { return a.dtype().attr("kind").cast<std::string>().at(0); }

void check_shape(const py::array& a, const std::string& group, const char* key, py::ssize_t rows,
                 const std::string& expected) {
  if (a.ndim() != 1 || (rows >= 0 && a.shape(0) != rows))
    fail(group, key, "expected " + expected + ", found shape " + shape_text(a));
}

std::vector<int32_t> int32_column(const py::array& a, const std::string& group, const char* key,
                                  py::ssize_t rows, const std::string& expected) {
  check_shape(a, group, key, rows, expected);
  const char kind = dtype_kind(a);
  if (kind != 'i' && kind != 'u')
    fail(group, key, "expected integers, found dtype " + py::str(a.dtype()).cast<std::string>());
  const auto v = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<int32_t> out(static_cast<std::size_t>(v.size()));
  for (py::ssize_t r = 0; r < v.size(); ++r) {
    const int64_t x = v.data()[r];
    if (x < std::numeric_limits<int32_t>::min() || x > std::numeric_limits<int32_t>::max() ||
        (kind == 'u' && v.data()[r] < 0))
      fail(group, key, "row " + std::to_string(r) + ": expected an int32 value, found " + std::to_string(x));
    out[static_cast<std::size_t>(r)] = static_cast<int32_t>(x);
  }
  return out;
}

py::array_t<double, py::array::c_style | py::array::forcecast> float_array(const py::array& a,
                                                                           const std::string& group,
                                                                           const char* key) {
  const char kind = dtype_kind(a);
  if (kind != 'f' && kind != 'i' && kind != 'u')
    fail(group, key, "expected real numbers, found dtype " + py::str(a.dtype()).cast<std::string>());
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
}

std::vector<double> float_column(const py::array& a, const std::string& group, const char* key,
                                 py::ssize_t rows, const std::string& expected) {
  check_shape(a, group, key, rows, expected);
  const auto v = float_array(a, group, key);
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace

TrackTable tracks_from_python(const py::handle& tracks) {
  if (!py::isinstance<py::dict>(tracks) && !py::isinstance<py::array>(tracks))
    throw InputError(
        std::string(kArraysSource) +
        ": expected a dict of arrays or a structured numpy array (sensor, track, t, state, cov), "
        "found " +
        py::str(py::type::of(tracks).attr("__name__")).cast<std::string>());
  const std::string g = "tracks";
  const py::array state = column(tracks, g, "state");
  if (state.ndim() != 2 || (state.shape(1) != 4 && state.shape(1) != 6))
    fail(g, "state",
         "expected N x 4 (x, y, vx, vy) or N x 6 (x, y, z, vx, vy, vz), found shape " + shape_text(state));
  const py::ssize_t n = state.shape(0);
  const int d = static_cast<int>(state.shape(1));
  const std::string rows = "N = " + std::to_string(n) + " values (as /tracks/state's rows)";
  TrackTable t(d == 4 ? StateLayout::kXY_VXVY : StateLayout::kXYZ_VXVYVZ);
  t.sensor = int32_column(column(tracks, g, "sensor"), g, "sensor", n, rows);
  t.track = int32_column(column(tracks, g, "track"), g, "track", n, rows);
  t.t = float_column(column(tracks, g, "t"), g, "t", n, rows);
  t.truth = has_field(tracks, "truth") ? int32_column(column(tracks, g, "truth"), g, "truth", n, rows)
                                       : std::vector<int32_t>(static_cast<std::size_t>(n), -1);
  const auto x = float_array(state, g, "state");
  for (int c = 0; c < d; ++c) {
    t.state[c].resize(static_cast<std::size_t>(n));
    for (py::ssize_t r = 0; r < n; ++r) t.state[c][r] = x.data()[r * d + c];
  }
  const py::array cov = column(tracks, g, "cov");
  const int p = packed_size(d);
  const bool packed = cov.ndim() == 2 && cov.shape(0) == n && cov.shape(1) == p;
  const bool full = cov.ndim() == 3 && cov.shape(0) == n && cov.shape(1) == d && cov.shape(2) == d;
  if (!packed && !full)
    fail(g, "cov",
         "expected N x " + std::to_string(p) + " (the packed upper triangle, row-major) or N x " +
             std::to_string(d) + " x " + std::to_string(d) + " with N = " + std::to_string(n) +
             ", found shape " + shape_text(cov));
  const auto c = float_array(cov, g, "cov");
  for (auto& col : t.cov) col.resize(static_cast<std::size_t>(n));
  for (py::ssize_t r = 0; r < n; ++r) {
    const double* m = c.data() + r * (packed ? p : d * d);
    for (int i = 0, k = 0; i < d; ++i)
      for (int j = i; j < d; ++j, ++k) {
        const double v = packed ? m[k] : m[i * d + j];
        // A full matrix must be symmetric: only its upper triangle would be kept otherwise.
        if (full && !(v == m[j * d + i]) && std::isfinite(v) &&
            std::abs(v - m[j * d + i]) > 1e-9 * std::max({std::abs(v), std::abs(m[j * d + i]), 1e-300}))
          fail(g, "cov",
               "row " + std::to_string(r) + ": expected a symmetric matrix, found (" + std::to_string(i) +
                   "," + std::to_string(j) + ") != (" + std::to_string(j) + "," + std::to_string(i) + ")");
        t.cov[k][r] = v;
      }
  }
  return t;
}

std::vector<Sensor> sensors_from_python(const py::handle& sensors, const TrackTable& tracks) {
  std::vector<Sensor> out;
  const std::string g = "sensors";
  if (sensors.is_none() || (!py::isinstance<py::dict>(sensors) && !py::isinstance<py::array>(sensors) &&
                            py::isinstance<py::sequence>(sensors))) {
    std::vector<int32_t> ids;
    if (sensors.is_none()) {
      const std::set<int32_t> in_tracks(tracks.sensor.begin(), tracks.sensor.end());
      ids.assign(in_tracks.begin(), in_tracks.end());
    } else {
      ids = int32_column(py::module_::import("numpy").attr("asarray")(sensors).cast<py::array>(), g, "id", -1,
                         "a list of sensor ids");
    }
    // The period of each sensor: the median interval between consecutive reports of its tracks.
    std::map<std::pair<int32_t, int32_t>, std::vector<double>> times;
    for (std::size_t r = 0; r < tracks.size(); ++r)
      times[{tracks.sensor[r], tracks.track[r]}].push_back(tracks.t[r]);
    std::map<int32_t, std::vector<double>> intervals;
    for (auto& [key, ts] : times) {
      std::sort(ts.begin(), ts.end());
      for (std::size_t k = 1; k < ts.size(); ++k) intervals[key.first].push_back(ts[k] - ts[k - 1]);
    }
    for (int32_t id : ids) {
      Sensor s;
      s.id = id;
      s.sigma_range = s.sigma_bearing = s.sigma_elevation = 0.0;  // unknown, as `import csv` leaves them
      s.period = median_interval(intervals[id]);
      if (!(s.period > 0))
        throw InputError(std::string(kArraysSource) + ": sensor " + std::to_string(id) +
                         ": no track of it reports twice, so its period cannot be estimated; give "
                         "sensors={'id': [...], 'period': [...]}");
      out.push_back(s);
    }
    return out;
  }
  if (!py::isinstance<py::dict>(sensors) && !py::isinstance<py::array>(sensors))
    throw InputError(std::string(kArraysSource) +
                     ": sensors: expected None, a list of ids or a dict of /sensors columns, found " +
                     py::str(py::type::of(sensors).attr("__name__")).cast<std::string>());
  const std::vector<int32_t> ids = int32_column(column(sensors, g, "id"), g, "id", -1, "a 1-D array of ids");
  const auto n = static_cast<py::ssize_t>(ids.size());
  out.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) out[i].id = ids[i];
  const std::string rows = "S = " + std::to_string(n) + " values (as /sensors/id)";
  const std::pair<const char*, double Sensor::*> scalars[] = {{"period", &Sensor::period},
                                                              {"offset", &Sensor::offset},
                                                              {"sigma_range", &Sensor::sigma_range},
                                                              {"sigma_bearing", &Sensor::sigma_bearing},
                                                              {"sigma_elevation", &Sensor::sigma_elevation},
                                                              {"p_detect", &Sensor::p_detect},
                                                              {"clutter_rate", &Sensor::clutter_rate},
                                                              {"reliability", &Sensor::reliability}};
  for (const auto& [key, member] : scalars)
    if (has_field(sensors, key)) {
      const auto v = float_column(column(sensors, g, key), g, key, n, rows);
      for (std::size_t i = 0; i < out.size(); ++i) out[i].*member = v[i];
    }
  if (has_field(sensors, "position")) {
    const py::array pos = column(sensors, g, "position");
    if (pos.ndim() != 2 || pos.shape(0) != n || pos.shape(1) != 3)
      fail(g, "position",
           "expected S x 3 with S = " + std::to_string(n) + ", found shape " + shape_text(pos));
    const auto p = float_array(pos, g, "position");
    for (std::size_t i = 0; i < out.size(); ++i)
      for (int k = 0; k < 3; ++k) out[i].position[k] = p.data()[i * 3 + k];
  }
  return out;
}

TrackFile track_file_from_python(const py::handle& tracks, const py::handle& sensors) {
  TrackFile file;
  file.tracks = tracks_from_python(tracks);
  file.sensors = sensors_from_python(sensors, file.tracks);
  track_validation::check_sensors(kArraysSource, file.sensors);
  track_validation::check_tracks(kArraysSource, file.tracks, file.sensors);
  return file;
}

py::array_t<double> columns_to_array(const std::vector<std::vector<double>>& columns, std::size_t rows) {
  const std::size_t d = columns.size();
  py::array_t<double> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(d)});
  double* out = a.mutable_data();
  for (std::size_t c = 0; c < d; ++c)
    for (std::size_t r = 0; r < rows; ++r) out[r * d + c] = columns[c][r];
  return a;
}

py::dict tracks_to_python(const TrackTable& t) {
  py::dict d;
  d["sensor"] = to_array(t.sensor);
  d["track"] = to_array(t.track);
  d["t"] = to_array(t.t);
  d["state"] = columns_to_array(t.state, t.size());
  d["cov"] = columns_to_array(t.cov, t.size());
  d["truth"] = to_array(t.truth);
  return d;
}

py::dict sensors_to_python(const std::vector<Sensor>& sensors) {
  py::dict d;
  auto column_of = [&](auto member) {
    using T = std::remove_cvref_t<decltype(sensors.front().*member)>;
    std::vector<T> v;
    for (const Sensor& s : sensors) v.push_back(s.*member);
    return to_array(v);
  };
  d["id"] = column_of(&Sensor::id);
  std::vector<double> pos;
  for (const Sensor& s : sensors) pos.insert(pos.end(), s.position.begin(), s.position.end());
  d["position"] = to_array(pos, sensors.size(), 3);
  d["sigma_range"] = column_of(&Sensor::sigma_range);
  d["sigma_bearing"] = column_of(&Sensor::sigma_bearing);
  d["sigma_elevation"] = column_of(&Sensor::sigma_elevation);
  d["period"] = column_of(&Sensor::period);
  d["offset"] = column_of(&Sensor::offset);
  d["p_detect"] = column_of(&Sensor::p_detect);
  d["clutter_rate"] = column_of(&Sensor::clutter_rate);
  d["reliability"] = column_of(&Sensor::reliability);
  return d;
}

nlohmann::json json_from_python(const py::handle& v, const std::string& what) {
  if (v.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  const py::module_ np = py::module_::import("numpy");
  if (py::isinstance(v, np.attr("bool_"))) return v.cast<bool>();
  if (py::isinstance<py::int_>(v) || py::isinstance(v, np.attr("integer"))) {
    const py::int_ i = py::reinterpret_borrow<py::object>(v).attr("__index__")();
    if (i.attr("__lt__")(0).cast<bool>()) {
      try {
        return i.cast<int64_t>();
      } catch (const py::cast_error&) {
      }
    } else {
      try {
        return i.cast<uint64_t>();
      } catch (const py::cast_error&) {
      }
    }
    throw InputError(what + ": the integer " + py::str(v).cast<std::string>() + " does not fit in 64 bits");
  }
  if (py::isinstance<py::float_>(v) || py::isinstance(v, np.attr("floating"))) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::dict>(v)) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [key, value] : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw InputError(what + ": expected str keys, found " + py::repr(key).cast<std::string>());
      const std::string k = key.cast<std::string>();
      j[k] = json_from_python(value, what + "['" + k + "']");
    }
    return j;
  }
  if (py::isinstance<py::array>(v)) return json_from_python(v.attr("tolist")(), what);
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    nlohmann::json j = nlohmann::json::array();
    std::size_t i = 0;
    for (const auto& item : v) j.push_back(json_from_python(item, what + "[" + std::to_string(i++) + "]"));
    return j;
  }
  throw InputError(what + ": expected a bool, number, str, list or dict, found " +
                   py::str(py::type::of(v).attr("__name__")).cast<std::string>());
}

py::object json_to_python(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

}  // namespace trackassoc::python
