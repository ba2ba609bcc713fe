// numpy <-> schema v1 content for the Python module (engine/python/module.cpp).
//
// A track set comes in as a dict of arrays or a structured numpy array with the /tracks columns:
//   sensor (N, int), track (N, int), t (N, float), state (N x 4 | N x 6, float),
//   cov (N x 10 | N x 21 packed upper triangle, row-major, or N x D x D, float), truth (N, int; optional)
// and the sensors as None, a list of ids, or a dict of /sensors columns (id required; period,
// position (S x 3), offset, sigma_range, sigma_bearing, sigma_elevation, p_detect, clutter_rate,
// reliability optional). The shapes and dtypes are checked here, then the content by the readers'
// own checks (io/track_validation.hpp: ids, finiteness, positive-definite covariances, duplicate
// rows), so an array fails with the message a file with the same content gets, naming "tracks" as
// the file. Errors are InputError (ValueError in Python).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

#include "io/track_file.hpp"

namespace trackassoc::python {

namespace py = pybind11;

// The name errors give as the "file" of a track set that came as arrays.
inline const char* kArraysSource = "tracks";

TrackTable tracks_from_python(const py::handle& tracks);
// `sensors` None: every sensor id of `tracks`, ascending, with its period the median interval
// between consecutive reports of one track (as `import csv` estimates it) and σ unknown (0).
std::vector<Sensor> sensors_from_python(const py::handle& sensors, const TrackTable& tracks);
// A validated TrackFile of the arrays (check_sensors, check_tracks).
TrackFile track_file_from_python(const py::handle& tracks, const py::handle& sensors);

py::dict tracks_to_python(const TrackTable& tracks);
py::dict sensors_to_python(const std::vector<Sensor>& sensors);

// Python values (None, bool, int, float, str, numpy scalars and arrays, lists, tuples, dicts with
// str keys) as JSON; anything else is an InputError naming `what`.
nlohmann::json json_from_python(const py::handle& value, const std::string& what);
py::object json_to_python(const nlohmann::json& value);

// A 1-D array of `values` (copied).
template <class T>
py::array_t<T> to_array(const std::vector<T>& values) {
  py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}
// A rows x cols array of a row-major `values` (copied).
template <class T>
py::array_t<T> to_array(const std::vector<T>& values, std::size_t rows, std::size_t cols) {
  py::array_t<T> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}
// The rows x columns array of column vectors ([columns][rows], as TrackTable::state).
py::array_t<double> columns_to_array(const std::vector<std::vector<double>>& columns, std::size_t rows);

}  // namespace trackassoc::python
