// Column helpers shared by the schema v1 group readers and writers (io/track_file.cpp,
// io/system_tracks_file.cpp, io/fused_tracks_file.cpp): an int32 column checked against a row count,
// a 1-D float64 column, a 2-D float64 table of a given shape, the state_layout attribute, and the
// [columns][rows] <-> row-major conversions.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/hdf5_wrapper.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc::h5 {

// A 1-D integer dataset as int32; `rows` is checked unless `reference` is empty (then any length).
inline std::vector<int32_t> read_int32_column(const Group& g, const std::string& name, std::size_t rows,
                                              const std::string& reference) {
  std::vector<hsize_t> dims;
  const std::vector<int64_t> wide = g.read_integers(name, 1, dims);
  if (!reference.empty() && dims[0] != rows)
    g.fail(name, "expected " + std::to_string(rows) + " rows (as " + reference + "), found " +
                     std::to_string(dims[0]));
  std::vector<int32_t> out(wide.size());
  for (std::size_t r = 0; r < wide.size(); ++r) {
    if (wide[r] < std::numeric_limits<int32_t>::min() || wide[r] > std::numeric_limits<int32_t>::max())
      g.fail(name, "row " + std::to_string(r) + ": value " + std::to_string(wide[r]) + " does not fit int32");
    out[r] = static_cast<int32_t>(wide[r]);
  }
  return out;
}

// A 1-D float64 dataset of `expected_rows` rows (as `reference`).
inline std::vector<double> read_1d(const Group& g, const std::string& name, std::size_t expected_rows,
                                   const std::string& reference) {
  std::vector<hsize_t> dims;
  std::vector<double> v = g.read_doubles(name, 1, dims);
  if (dims[0] != expected_rows)
    g.fail(name, "expected " + std::to_string(expected_rows) + " rows (as " + reference + "), found " +
                     std::to_string(dims[0]));
  return v;
}

// The string attribute state_layout of `g`: "x,y,vx,vy" or "x,y,z,vx,vy,vz".
inline StateLayout read_layout(const Group& g, const std::string& file) {
  const std::string layout = g.read_string_attribute("state_layout");
  if (layout == layout_name(StateLayout::kXY_VXVY)) return StateLayout::kXY_VXVY;
  if (layout == layout_name(StateLayout::kXYZ_VXVYVZ)) return StateLayout::kXYZ_VXVYVZ;
  throw InputError(file + ": " + g.path() +
                   " attribute state_layout: expected \"x,y,vx,vy\" or \"x,y,z,vx,vy,vz\", found \"" +
                   layout + "\"");
}

// A 2-D float64 dataset of shape rows×cols (row-major), `what` describing the expected shape.
inline std::vector<double> read_table_2d(const Group& g, const std::string& name, std::size_t rows,
                                         std::size_t cols, const std::string& what) {
  std::vector<hsize_t> dims;
  std::vector<double> v = g.read_doubles(name, 2, dims);
  if (dims[0] != rows || dims[1] != cols)
    g.fail(name, "expected shape " + std::to_string(rows) + "x" + std::to_string(cols) + " (" + what +
                     "), found " + shape_text(dims));
  return v;
}

// [D][rows] columns to a rows×D row-major buffer, and back. The copy for a writer is checked
// against the memory budget beside what the process holds (an output is written at the end, when
// it holds the most).
inline std::vector<double> rows_from_columns(const std::vector<std::vector<double>>& columns,
                                             std::size_t rows) {
  const std::size_t d = columns.size();
  require_memory_beside_held(
      0.0, static_cast<double>(rows) * static_cast<double>(d) * sizeof(double),
      "writing a table of " + std::to_string(rows) + " rows of " + std::to_string(d) + " values");
  std::vector<double> out(rows * d);
  for (std::size_t c = 0; c < d; ++c)
    for (std::size_t r = 0; r < rows; ++r) out[r * d + c] = columns[c][r];
  return out;
}

inline std::vector<std::vector<double>> columns_from_rows(const std::vector<double>& data, std::size_t rows,
                                                          std::size_t d) {
  std::vector<std::vector<double>> out(d, std::vector<double>(rows));
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < d; ++c) out[c][r] = data[r * d + c];
  return out;
}

}  // namespace trackassoc::h5
