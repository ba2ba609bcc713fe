// The column mapping, the per-sensor value flags and the CSV export of io/csv_tracks.hpp.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/csv_tracks.hpp"
#include "io/json_input.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc {
namespace {

using json = nlohmann::json;

// The state components of a layout, in state order (docs/design.md §3).
std::vector<std::string> component_names(StateLayout layout) {
  if (layout == StateLayout::kXY_VXVY) return {"x", "y", "vx", "vy"};
  return {"x", "y", "z", "vx", "vy", "vz"};
}

// The string members of CsvColumnMapping by mapping key.
std::vector<std::pair<const char*, std::string CsvColumnMapping::*>> string_keys() {
  return {{"time", &CsvColumnMapping::time},   {"sensor", &CsvColumnMapping::sensor},
          {"track", &CsvColumnMapping::track}, {"truth", &CsvColumnMapping::truth},
          {"x", &CsvColumnMapping::x},         {"y", &CsvColumnMapping::y},
          {"z", &CsvColumnMapping::z},         {"lat", &CsvColumnMapping::lat},
          {"lon", &CsvColumnMapping::lon},     {"alt", &CsvColumnMapping::alt},
          {"vx", &CsvColumnMapping::vx},       {"vy", &CsvColumnMapping::vy},
          {"vz", &CsvColumnMapping::vz}};
}

std::string known_keys() {
  std::string s;
  for (const auto& [key, member] : string_keys()) s += std::string(key) + ", ";
  return s + "cov, sigma";
}

std::string column_name(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_string() || v.get<std::string>().empty())
    throw InputError(source + ": mapping key " + quoted_preview(key, 80) +
                     ": expected a column name (a non-empty string), found " + v.dump().substr(0, 80));
  return v.get<std::string>();
}

std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

CsvColumnMapping parse_csv_mapping(const std::string& json_text, const std::string& source) {
  const json j = parse_json_input(json_text, source);
  if (!j.is_object()) throw InputError(source + ": expected a JSON object mapping fields to column names");
  CsvColumnMapping m;
  const auto keys = string_keys();
  for (const auto& item : j.items()) {
    const std::string key = item.key();
    const json& value = item.value();
    auto it = std::find_if(keys.begin(), keys.end(), [&](const auto& k) { return key == k.first; });
    if (it != keys.end()) {
      m.*(it->second) = column_name(value, source, key);
    } else if (key == "cov") {
      if (!value.is_array())
        throw InputError(source +
                         ": mapping key 'cov': expected an array of column names (the packed upper "
                         "triangle), found " +
                         value.dump().substr(0, 80));
      for (std::size_t i = 0; i < value.size(); ++i)
        m.cov.push_back(column_name(value[i], source, "cov[" + std::to_string(i) + "]"));
    } else if (key == "sigma") {
      if (!value.is_object())
        throw InputError(source + ": mapping key 'sigma': expected an object {\"x\": column, ...}, found " +
                         value.dump().substr(0, 80));
      for (const auto& [component, column] : value.items())
        m.sigma[component] = column_name(column, source, "sigma." + component);
    } else {
      throw InputError(source + ": mapping key " + quoted_preview(key, 80) +
                       " is unknown (known: " + known_keys() + ")");
    }
  }
  return m;
}

std::string csv_mapping_to_json(const CsvColumnMapping& m) {
  json j = json::object();
  for (const auto& [key, member] : string_keys())
    if (!(m.*member).empty()) j[key] = m.*member;
  if (!m.cov.empty()) j["cov"] = m.cov;
  if (!m.sigma.empty()) j["sigma"] = m.sigma;
  return j.dump(1);
}

void set_csv_mapping_entry(CsvColumnMapping& m, const std::string& entry) {
  const auto eq = entry.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == entry.size())
    throw InputError("--column: expected KEY=COLUMN (e.g. time=t, cov=c0,c1,..., sigma.x=sx), found '" +
                     entry + "'");
  const std::string key = entry.substr(0, eq), column = entry.substr(eq + 1);
  for (const auto& [name, member] : string_keys())
    if (key == name) {
      m.*member = column;
      return;
    }
  if (key == "cov") {
    m.cov.clear();
    std::size_t start = 0;
    while (start <= column.size()) {
      const std::size_t comma = std::min(column.find(',', start), column.size());
      if (comma == start) throw InputError("--column cov: empty column name in '" + column + "'");
      m.cov.push_back(column.substr(start, comma - start));
      start = comma + 1;
    }
  } else if (key.rfind("sigma.", 0) == 0 && key.size() > 6) {
    m.sigma[key.substr(6)] = column;
  } else {
    throw InputError("--column: key '" + key + "' is unknown (known: " + known_keys() + " as sigma.x, ...)");
  }
}

std::optional<double> PerSensorValue::for_sensor(int32_t id) const {
  auto it = by_sensor.find(id);
  if (it != by_sensor.end()) return it->second;
  return all;
}

PerSensorValue parse_per_sensor_value(const std::string& text, const std::string& flag) {
  PerSensorValue v;
  auto number = [&](std::string_view s, auto& out, const char* what) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size())
      throw InputError(flag + ": expected " + std::string(what) + ", found '" + std::string(s) + "' in '" +
                       text + "' (the form is V, S:V,S:V or V,S:V)");
  };
  std::string_view rest = text;
  if (rest.empty()) throw InputError(flag + ": empty value (the form is V, S:V,S:V or V,S:V)");
  while (true) {
    const std::size_t comma = std::min(rest.find(','), rest.size());
    const std::string_view item = rest.substr(0, comma);
    const std::size_t colon = item.find(':');
    double value = 0;
    number(colon == std::string_view::npos ? item : item.substr(colon + 1), value, "a number");
    if (!(std::isfinite(value) && value > 0))
      throw InputError(flag + ": expected a value > 0, found '" + std::string(item) + "'");
    if (colon == std::string_view::npos) {
      if (v.all) throw InputError(flag + ": two values for every sensor in '" + text + "'");
      v.all = value;
    } else {
      int32_t id = 0;
      number(item.substr(0, colon), id, "a sensor id (an integer)");
      if (!v.by_sensor.emplace(id, value).second)
        throw InputError(flag + ": sensor " + std::to_string(id) + " given twice in '" + text + "'");
    }
    if (comma == rest.size()) break;
    rest.remove_prefix(comma + 1);
  }
  return v;
}

CsvColumnMapping read_csv_mapping_file(const std::string& path, const std::string& flag) {
  check_input_file(path, flag, "mapping JSON file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return parse_csv_mapping(text.str(), path);
}

std::array<double, 3> parse_geodetic_origin(const std::string& text, const std::string& flag) {
  std::array<double, 3> o{0, 0, 0};
  std::string_view rest = text;
  int n = 0;
  while (n < 3) {
    const std::size_t comma = std::min(rest.find(','), rest.size());
    const std::string_view item = rest.substr(0, comma);
    const auto r = std::from_chars(item.data(), item.data() + item.size(), o[n]);
    if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size() || !std::isfinite(o[n]))
      throw InputError(flag + ": expected LAT,LON[,ALT] (degrees, degrees, metres), found '" + text + "'");
    ++n;
    if (comma == rest.size()) break;
    rest.remove_prefix(comma + 1);
    if (n == 3)
      throw InputError(flag + ": expected LAT,LON[,ALT], found more than three numbers in '" + text + "'");
  }
  if (n < 2) throw InputError(flag + ": expected LAT,LON[,ALT], found '" + text + "'");
  return o;
}

char parse_csv_delimiter(const std::string& text, const std::string& flag) {
  if (text == "," || text == "comma") return ',';
  if (text == ";" || text == "semicolon") return ';';
  if (text == "\t" || text == "tab" || text == "\\t") return '\t';
  throw InputError(flag + ": expected ',', ';' or 'tab', found '" + text + "'");
}

void CsvImportOptions::validate() const {
  const CsvColumnMapping& m = columns;
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("mapping: " + what);
  };
  need(!m.time.empty(), "key 'time' is required (the column of report times [s])");
  need(!m.sensor.empty(), "key 'sensor' is required (the column of sensor ids)");
  need(!m.track.empty(), "key 'track' is required (the column of local track numbers)");
  const bool cartesian = !m.x.empty() || !m.y.empty() || !m.z.empty();
  need(!(cartesian && m.geodetic()), "give x, y[, z] or lat, lon[, alt], not both");
  if (m.geodetic()) {
    need(!m.lat.empty() && !m.lon.empty(), "geodetic input needs both 'lat' and 'lon' ('alt' is optional)");
  } else {
    need(!m.x.empty() && !m.y.empty(), "keys 'x' and 'y' (or 'lat' and 'lon') are required");
  }
  const bool any_velocity = !m.vx.empty() || !m.vy.empty() || !m.vz.empty();
  if (any_velocity) {
    need(!m.vx.empty() && !m.vy.empty(),
         "give both 'vx' and 'vy', or no velocity column (then it is estimated)");
    need(m.three_d() == !m.vz.empty(), m.three_d()
                                           ? "a 3-D position ('z' or 'alt') needs 'vz' with 'vx', 'vy'"
                                           : "'vz' needs a 3-D position ('z' or 'alt')");
  }
  const StateLayout layout = m.three_d() ? StateLayout::kXYZ_VXVYVZ : StateLayout::kXY_VXVY;
  const int d = state_dim(layout);
  if (!m.cov.empty()) {
    need(static_cast<int>(m.cov.size()) == packed_size(d),
         "key 'cov': expected " + std::to_string(packed_size(d)) + " columns (the packed upper triangle of " +
             layout_name(layout) + "), found " + std::to_string(m.cov.size()));
    need(m.sigma.empty(), "give 'cov' or 'sigma', not both");
  }
  const std::vector<std::string> names = component_names(layout);
  for (const auto& [component, column] : m.sigma)
    need(std::find(names.begin(), names.end(), component) != names.end(),
         "key 'sigma." + component + "': expected a state component of " + layout_name(layout));
  need(delimiter == ',' || delimiter == ';' || delimiter == '\t', "the delimiter must be ',', ';' or tab");
  if (origin) {
    const auto& o = *origin;
    require(m.geodetic(), "--origin", "only for geodetic input (lat, lon columns)");
    require(o[0] >= -90 && o[0] <= 90, "--origin",
            "expected a latitude in [-90, 90], found " + number_text(o[0]));
    require(o[1] >= -180 && o[1] <= 360, "--origin",
            "expected a longitude in [-180, 360], found " + number_text(o[1]));
    require(std::isfinite(o[2]), "--origin", "expected a finite height [m]");
  }
  std::set<int32_t> seen;
  for (int32_t s : sensors)
    require(seen.insert(s).second, "--sensors", "sensor " + std::to_string(s) + " given twice");
  require(max_errors >= 1, "CsvImportOptions.max_errors", "must be >= 1");
}

CsvColumnMapping csv_export_mapping(StateLayout layout) {
  CsvColumnMapping m;
  m.time = "t";
  m.sensor = "sensor";
  m.track = "track";
  m.truth = "truth";
  const std::vector<std::string> names = component_names(layout);
  const int d = state_dim(layout);
  m.x = "x";
  m.y = "y";
  if (d == 6) m.z = "z";
  m.vx = "vx";
  m.vy = "vy";
  if (d == 6) m.vz = "vz";
  for (int r = 0; r < d; ++r)
    for (int c = r; c < d; ++c) m.cov.push_back("cov_" + names[r] + "_" + names[c]);
  return m;
}

void export_csv_tracks(const TrackFile& file, std::ostream& out, char delimiter) {
  const TrackTable& t = file.tracks;
  const int d = t.dim(), p = packed_size(d);
  const CsvColumnMapping m = csv_export_mapping(t.layout);
  std::string line = "sensor" + std::string(1, delimiter) + "track" + delimiter + "t";
  for (const std::string& c : component_names(t.layout)) line += delimiter + c;
  for (const std::string& c : m.cov) line += delimiter + c;
  line += delimiter + std::string("truth\n");
  out << line;
  char buf[64];
  std::string chunk;
  chunk.reserve(1 << 20);
  auto put = [&](auto v) {
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back exactly
    chunk.append(buf, r.ptr);
  };
  for (std::size_t r = 0; r < t.size(); ++r) {
    put(t.sensor[r]);
    chunk += delimiter;
    put(t.track[r]);
    chunk += delimiter;
    put(t.t[r]);
    for (int c = 0; c < d; ++c) {
      chunk += delimiter;
      put(t.state[c][r]);
    }
    for (int k = 0; k < p; ++k) {
      chunk += delimiter;
      put(t.cov[k][r]);
    }
    chunk += delimiter;
    put(t.truth[r]);
    chunk += '\n';
    if (chunk.size() > (1 << 20) - 1024) {
      out << chunk;
      chunk.clear();
    }
  }
  out << chunk;
}

void write_csv_tracks(const std::string& path, const TrackFile& file, char delimiter) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(path + ": cannot open for writing");
    export_csv_tracks(file, out, delimiter);
    out.close();
    if (!out) throw InputError(path + ": write failed (disk full?)");
  });
}

}  // namespace trackassoc
