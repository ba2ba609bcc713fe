#include "io/system_tracks_file.hpp"

#include <cmath>
#include <limits>
#include <set>

#include "io/hdf5_columns.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using h5::Group;

std::vector<int32_t> read_int32_column(const Group& g, const std::string& name, std::size_t rows) {
  return h5::read_int32_column(g, name, rows, g.child_path(name == "track" ? "t" : "sensor"));
}

}  // namespace

void check_system_tracks(const std::string& file, const SystemTrackRecord& r,
                         const std::vector<Sensor>& sensors) {
  const std::string where = file + ": /system_tracks/" + r.name;
  require(!r.name.empty() && r.name.find('/') == std::string::npos, where,
          "group name must be non-empty without '/'");
  const std::size_t n = r.size();
  require(r.track.size() == n, where + "/track", "expected " + std::to_string(n) + " rows (as t)");
  for (const auto& c : r.state)
    require(c.size() == n, where + "/state", "expected " + std::to_string(n) + " rows");
  for (std::size_t i = 0; i < n; ++i) {
    bool finite = std::isfinite(r.t[i]);
    for (const auto& c : r.state) finite = finite && std::isfinite(c[i]);
    require(finite, where, "row " + std::to_string(i) + ": t and state must be finite");
    require(r.track[i] >= 0, where + "/track", "row " + std::to_string(i) + ": expected >= 0");
  }
  const std::size_t m = r.mapping_size();
  require(r.map_local_track.size() == m && r.map_system_track.size() == m && r.map_packets.size() == m,
          where + "/mapping", "sensor, local_track, system_track and packets must have the same length");
  std::set<int32_t> ids;
  for (const auto& s : sensors) ids.insert(s.id);
  for (std::size_t i = 0; i < m; ++i)
    require(ids.count(r.map_sensor[i]) > 0, where + "/mapping/sensor",
            "row " + std::to_string(i) + ": " + std::to_string(r.map_sensor[i]) + " is not a /sensors id");
}

void write_system_tracks(const Group& root, const std::vector<SystemTrackRecord>& records) {
  if (records.empty()) return;
  const Group parent = root.create_group("system_tracks", /*track_order=*/true);
  for (const auto& r : records) {
    const Group g = parent.create_group(r.name);
    g.write_attribute("method", r.method);
    g.write_attribute("options", r.options_json);
    g.write_attribute("state_layout", std::string(layout_name(StateLayout::kXY_VXVY)));
    const std::size_t n = r.size();
    g.write_dataset("track", std::span<const int32_t>(r.track), {n});
    g.write_dataset("t", std::span<const double>(r.t), {n});
    std::vector<double> rows(n * 4);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) rows[i * 4 + c] = r.state[c][i];
    g.write_dataset("state", std::span<const double>(rows), {n, 4});
    const Group m = g.create_group("mapping");
    const std::size_t k = r.mapping_size();
    m.write_dataset("sensor", std::span<const int32_t>(r.map_sensor), {k});
    m.write_dataset("local_track", std::span<const int32_t>(r.map_local_track), {k});
    m.write_dataset("system_track", std::span<const int32_t>(r.map_system_track), {k});
    m.write_dataset("packets", std::span<const int32_t>(r.map_packets), {k});
  }
}

std::vector<SystemTrackRecord> read_system_tracks(const Group& root) {
  std::vector<SystemTrackRecord> out;
  if (!root.has("system_tracks")) return out;
  const Group parent = root.open_group("system_tracks");
  for (const std::string& name : parent.children()) {
    const Group g = parent.open_group(name);
    SystemTrackRecord r;
    r.name = name;
    r.method = g.has_attribute("method") ? g.read_string_attribute("method") : "";
    r.options_json = g.has_attribute("options") ? g.read_string_attribute("options") : "{}";
    std::vector<hsize_t> dims;
    r.t = g.read_doubles("t", 1, dims);
    const std::size_t n = dims[0];
    r.track = read_int32_column(g, "track", n);
    const std::vector<double> rows = g.read_doubles("state", 2, dims);
    if (dims[0] != n || dims[1] != 4)
      g.fail("state",
             "expected shape " + std::to_string(n) + "x4 (x, y, vx, vy), found " + h5::shape_text(dims));
    for (int c = 0; c < 4; ++c) {
      r.state[c].resize(n);
      for (std::size_t i = 0; i < n; ++i) r.state[c][i] = rows[i * 4 + c];
    }
    const Group m = g.open_group("mapping");
    const std::vector<hsize_t> shape = m.dataset_shape("sensor");
    if (shape.size() != 1) m.fail("sensor", "expected a 1-D dataset, found " + h5::shape_text(shape));
    const std::size_t k = shape[0];
    r.map_sensor = read_int32_column(m, "sensor", k);
    r.map_local_track = read_int32_column(m, "local_track", k);
    r.map_system_track = read_int32_column(m, "system_track", k);
    r.map_packets = read_int32_column(m, "packets", k);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace trackassoc
