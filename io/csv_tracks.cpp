// CSV import of recorded track files (io/csv_tracks.hpp): streamed line by line, every bad value
// named by line and column, then the velocity estimate and the /sensors rows.
#include "io/csv_tracks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>
#include <unordered_map>

#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/geodetic.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc {
namespace {

// What a mapped column holds.
enum class Kind { kTime, kSensor, kTrack, kTruth, kPosition, kVelocity, kCov, kSigma };

struct Slot {
  std::string key, column;  // mapping key ("x", "cov[3]", "sigma.vx") and CSV column name
  Kind kind;
  int index = 0;  // component (position/velocity: 0..2; sigma: state index), or packed cov index
};

std::string quoted_field(std::string_view s) { return quoted_preview(s, 40); }

// Reads line `line_number` of `in` (without its '\n') into `line`, as std::getline does, but never
// more than kMaxCsvLineBytes of it: a longer line is refused here, naming it, before it is held
// whole (a 200 MB header line took 834 MB). False at the end of the input. A NUL byte is refused:
// UTF-8 text never holds one (kernels/core/printable_text.hpp).
bool read_csv_line(std::istream& in, std::string& line, std::size_t line_number, const std::string& source) {
  line.clear();
  char chunk[4096];
  while (true) {
    in.getline(chunk, sizeof chunk);
    const auto n = static_cast<std::size_t>(in.gcount());
    // A full chunk without its '\n' sets failbit: the line goes on. Otherwise the '\n' was
    // extracted (counted in n, not stored), or the input ended (eofbit), or it failed.
    const bool more = !in.eof() && !in.bad() && in.fail() && n == sizeof chunk - 1;
    const bool newline = !in.fail() && !in.eof();
    line.append(chunk, newline ? n - 1 : n);
    if (line.size() > kMaxCsvLineBytes)
      throw InputError(source + ": line " + std::to_string(line_number) + " is longer than " +
                       std::to_string(kMaxCsvLineBytes) +
                       " bytes (the cap of a CSV line); is it a CSV file?");
    if (!more) break;
    in.clear();
  }
  if (line.find('\0') != std::string::npos)
    throw InputError(source + ": line " + std::to_string(line_number) + ": " +
                     not_utf8_text_reason(line, "UTF-8 CSV"));
  return !line.empty() || (!in.fail() && !in.eof());  // an empty line ends with its '\n'
}

std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// Whitespace around a field is not part of the value.
std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Splits `line` at `delimiter` into `fields` (views into line), RFC 4180 style: a field whose
// first non-blank character is '"' runs to its closing quote, so it may hold the delimiter, and
// "" inside it is a quote (the view keeps it doubled: a column we read is a number or a name,
// where a quote is an error anyway). Returns false on a quoted field with no closing quote (a
// quoted line break is not supported: records are single lines).
bool split(std::string_view line, char delimiter, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  while (true) {
    std::size_t end;
    std::size_t q = start;
    while (q < line.size() && line[q] != delimiter && (line[q] == ' ' || line[q] == '\t')) ++q;
    if (q < line.size() && line[q] == '"') {
      std::size_t close = q + 1;
      while (true) {
        close = line.find('"', close);
        if (close == std::string_view::npos) return false;
        if (close + 1 < line.size() && line[close + 1] == '"') {
          close += 2;  // "" inside the quotes
          continue;
        }
        break;
      }
      end = line.find(delimiter, close + 1);
      // The value: inside the quotes (blanks between the closing quote and the delimiter dropped).
      const std::string_view rest = trim(
          line.substr(close + 1, end == std::string_view::npos ? std::string_view::npos : end - close - 1));
      if (!rest.empty()) return false;  // text after the closing quote
      fields.push_back(line.substr(q + 1, close - q - 1));
    } else {
      end = line.find(delimiter, start);
      fields.push_back(
          trim(line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    }
    if (end == std::string_view::npos) return true;
    start = end + 1;
  }
}

// The bad values found so far: the first `limit` messages, and how many in all.
class Errors {
 public:
  Errors(std::string source, std::size_t limit) : source_(std::move(source)), limit_(limit) {}
  void add(std::size_t line, const std::string& column, const std::string& what) {
    if (++count_ <= limit_)
      messages_.push_back("line " + std::to_string(line) + ", column '" + printable_text(column) +
                          "': " + what);
  }
  void add_line(std::size_t line, const std::string& what) {
    if (++count_ <= limit_) messages_.push_back("line " + std::to_string(line) + ": " + what);
  }
  std::size_t count() const { return count_; }
  void throw_if_any() const {
    if (count_ == 0) return;
    std::string text = source_ + ": ";
    if (count_ > 1)
      text += std::to_string(count_) + " bad values" +
              (count_ > messages_.size() ? " (the first " + std::to_string(messages_.size()) + ")" : "") +
              ": ";
    for (std::size_t i = 0; i < messages_.size(); ++i) text += (i ? "; " : "") + messages_[i];
    throw InputError(text);
  }

 private:
  std::string source_;
  std::size_t limit_, count_ = 0;
  std::vector<std::string> messages_;
};

// Parses a finite double; the error text otherwise.
std::string parse_double(std::string_view s, double& out) {
  if (s.empty()) return "empty field, expected a number";
  std::string_view body = s.front() == '+' ? s.substr(1) : s;
  const auto r = std::from_chars(body.data(), body.data() + body.size(), out);
  if (r.ec == std::errc::result_out_of_range) return "number out of the double range: " + quoted_field(s);
  if (r.ec != std::errc() || r.ptr != body.data() + body.size())
    return "expected a number, found " + quoted_field(s);
  if (!std::isfinite(out)) return "expected a finite number, found " + quoted_field(s);
  return "";
}

std::string parse_int32(std::string_view s, int32_t& out) {
  if (s.empty()) return "empty field, expected an integer";
  std::string_view body = s.front() == '+' ? s.substr(1) : s;
  int64_t v = 0;
  const auto r = std::from_chars(body.data(), body.data() + body.size(), v);
  if (r.ec != std::errc() || r.ptr != body.data() + body.size())
    return "expected an integer, found " + quoted_field(s);
  if (v < INT32_MIN || v > INT32_MAX) return "integer " + quoted_field(s) + " does not fit int32";
  out = static_cast<int32_t>(v);
  return "";
}

uint64_t track_key(int32_t sensor, int32_t track) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(sensor)) << 32) | static_cast<uint32_t>(track);
}

// The reports of one local track, in file (= time) order.
struct TrackRows {
  int32_t sensor, track;
  double last_t;
  std::size_t last_line;
  std::vector<std::size_t> rows;
};

std::vector<Slot> mapped_slots(const CsvColumnMapping& m, int d) {
  std::vector<Slot> slots;
  auto add = [&](const std::string& key, const std::string& column, Kind kind, int index) {
    if (!column.empty()) slots.push_back({key, column, kind, index});
  };
  add("time", m.time, Kind::kTime, 0);
  add("sensor", m.sensor, Kind::kSensor, 0);
  add("track", m.track, Kind::kTrack, 0);
  add("truth", m.truth, Kind::kTruth, 0);
  const bool g = m.geodetic();
  add(g ? "lat" : "x", g ? m.lat : m.x, Kind::kPosition, 0);
  add(g ? "lon" : "y", g ? m.lon : m.y, Kind::kPosition, 1);
  add(g ? "alt" : "z", g ? m.alt : m.z, Kind::kPosition, 2);
  add("vx", m.vx, Kind::kVelocity, 0);
  add("vy", m.vy, Kind::kVelocity, 1);
  add("vz", m.vz, Kind::kVelocity, 2);
  for (std::size_t k = 0; k < m.cov.size(); ++k)
    add("cov[" + std::to_string(k) + "]", m.cov[k], Kind::kCov, static_cast<int>(k));
  const char* names4[] = {"x", "y", "vx", "vy"};
  const char* names6[] = {"x", "y", "z", "vx", "vy", "vz"};
  for (int c = 0; c < d; ++c) {
    auto it = m.sigma.find(d == 4 ? names4[c] : names6[c]);
    if (it != m.sigma.end()) add("sigma." + it->first, it->second, Kind::kSigma, c);
  }
  return slots;
}

// Reads the header line and binds every slot to its column; slot_of[column] = slot or -1.
std::vector<int> bind_header(std::istream& in, const std::string& source, char delimiter,
                             const std::vector<Slot>& slots, std::size_t& columns) {
  std::string header;
  if (!read_csv_line(in, header, 1, source))
    throw InputError(source + ": empty file; expected a header row naming the columns");
  if (header.size() >= 3 && header.compare(0, 3, "\xEF\xBB\xBF") == 0) header.erase(0, 3);  // UTF-8 BOM
  std::vector<std::string_view> names;
  if (!split(header, delimiter, names))
    throw InputError(source +
                     ": line 1 (the header): a quoted field without its closing quote, or text after it");
  columns = names.size();
  std::vector<int> slot_of(columns, -1);
  for (std::size_t s = 0; s < slots.size(); ++s) {
    int found = -1;
    for (std::size_t c = 0; c < columns; ++c)
      if (names[c] == slots[s].column) {
        if (found >= 0)
          throw InputError(source + ": line 1: column '" + printable_text(slots[s].column) +
                           "' (mapping key '" + slots[s].key + "') appears twice in the header");
        found = static_cast<int>(c);
      }
    if (found < 0) {
      std::string list;
      for (std::size_t c = 0; c < std::min<std::size_t>(columns, 30); ++c)
        list += (c ? ", " : "") + printable_text(names[c].substr(0, 80));
      throw InputError(
          source + ": mapping key '" + slots[s].key + "': column '" + printable_text(slots[s].column) +
          "' is not in the header (line 1: " + list + (columns > 30 ? ", ..." : "") +
          "; names are matched exactly" +
          (delimiter == ',' && header.find(';') != std::string::npos ? "; is the delimiter ';'?" : "") + ")");
    }
    if (slot_of[found] >= 0)
      throw InputError(source + ": mapping keys '" + slots[slot_of[found]].key + "' and '" + slots[s].key +
                       "' name the same column '" + printable_text(slots[s].column) + "'");
    slot_of[found] = static_cast<int>(s);
  }
  return slot_of;
}

// Velocity of the reports `rows` of one track from their positions (three-point Lagrange
// derivative, one-sided at the ends, 0 for one report); returns the row of a non-finite result.
std::optional<std::size_t> estimate_track_velocity(TrackTable& t, const std::vector<std::size_t>& rows) {
  const int sd = t.dim() / 2;
  const std::size_t n = rows.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t r = rows[k];
    for (int c = 0; c < sd; ++c) {
      double v = 0.0;
      if (n >= 3 && k > 0 && k + 1 < n) {
        const std::size_t a = rows[k - 1], b = rows[k + 1];
        const double h0 = t.t[r] - t.t[a], h1 = t.t[b] - t.t[r];
        const double d0 = (t.state[c][r] - t.state[c][a]) / h0, d1 = (t.state[c][b] - t.state[c][r]) / h1;
        v = (h1 * d0 + h0 * d1) / (h0 + h1);  // derivative at t_k of the parabola through the three reports
      } else if (n >= 2) {
        const std::size_t a = k == 0 ? rows[0] : rows[k - 1], b = k == 0 ? rows[1] : rows[k];
        v = (t.state[c][b] - t.state[c][a]) / (t.t[b] - t.t[a]);
      }
      if (!std::isfinite(v)) return r;
      t.state[sd + c][r] = v;
    }
  }
  return std::nullopt;
}

}  // namespace

double median_interval(std::vector<double>& intervals) {
  if (intervals.empty()) return 0.0;
  auto mid = intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2);
  std::nth_element(intervals.begin(), mid, intervals.end());
  return std::round(*mid * 1e6) / 1e6;
}

TrackFile import_csv_tracks(std::istream& in, const std::string& source, const CsvImportOptions& o,
                            CsvImportSummary* summary) {
  o.validate();
  const CsvColumnMapping& m = o.columns;
  const StateLayout layout = m.three_d() ? StateLayout::kXYZ_VXVYVZ : StateLayout::kXY_VXVY;
  const int d = state_dim(layout), sd = d / 2, p = packed_size(d);
  const bool geodetic = m.geodetic(), has_velocity = !m.vx.empty(), has_cov = !m.cov.empty();
  const std::vector<Slot> slots = mapped_slots(m, d);
  std::size_t columns = 0;
  const std::vector<int> slot_of = bind_header(in, source, o.delimiter, slots, columns);

  TrackFile file;
  TrackTable& t = file.tracks;
  t.reset(layout);
  Errors errors(source, o.max_errors);
  const std::set<int32_t> known(o.sensors.begin(), o.sensors.end());
  std::optional<EnuFrame> frame;
  if (geodetic && o.origin) frame.emplace((*o.origin)[0], (*o.origin)[1], (*o.origin)[2]);
  std::unordered_map<uint64_t, std::size_t> track_index;
  std::vector<TrackRows> tracks;
  std::map<int32_t, std::array<bool, 6>> assumed;  // sensor -> components whose σ came from a flag
  std::set<int32_t> sensors_without_sigma;

  std::string line;
  std::vector<std::string_view> fields;
  std::vector<double> value(slots.size());
  std::vector<int32_t> id(slots.size());
  std::size_t line_number = 1;
  while (read_csv_line(in, line, line_number + 1, source)) {
    ++line_number;
    if (trim(line).empty()) continue;  // blank lines (a trailing newline, a spreadsheet's empty rows)
    if (!split(line, o.delimiter, fields)) {
      errors.add_line(line_number, "a quoted field without its closing quote, or text after it");
      continue;
    }
    const std::size_t before = errors.count();
    if (fields.size() != columns) {
      errors.add_line(line_number, std::to_string(fields.size()) + " fields, the header has " +
                                       std::to_string(columns) +
                                       (fields.size() < columns ? " (missing fields)" : " (extra fields)"));
      continue;
    }
    for (std::size_t c = 0; c < columns; ++c) {
      if (slot_of[c] < 0) continue;
      const Slot& s = slots[slot_of[c]];
      const bool integer = s.kind == Kind::kSensor || s.kind == Kind::kTrack || s.kind == Kind::kTruth;
      const std::string why =
          integer ? parse_int32(fields[c], id[slot_of[c]]) : parse_double(fields[c], value[slot_of[c]]);
      if (!why.empty()) errors.add(line_number, s.column, why);
    }
    if (errors.count() != before) continue;
    // Gather the fields of the row by meaning.
    double time = 0, pos[3] = {0, 0, 0}, vel[3] = {0, 0, 0}, cov[21], sigma[6] = {0, 0, 0, 0, 0, 0};
    int32_t sensor = 0, track = 0, truth = -1;
    bool sigma_given[6] = {false, false, false, false, false, false};
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const Slot& slot = slots[s];
      switch (slot.kind) {
        case Kind::kTime:
          time = value[s];
          break;
        case Kind::kSensor:
          sensor = id[s];
          break;
        case Kind::kTrack:
          track = id[s];
          break;
        case Kind::kTruth:
          truth = id[s];
          break;
        case Kind::kPosition:
          pos[slot.index] = value[s];
          break;
        case Kind::kVelocity:
          vel[slot.index] = value[s];
          break;
        case Kind::kCov:
          cov[slot.index] = value[s];
          break;
        case Kind::kSigma:
          sigma[slot.index] = value[s];
          sigma_given[slot.index] = true;
          if (!(value[s] > 0))
            errors.add(line_number, slot.column, "expected a σ > 0, found " + number_text(value[s]));
          break;
      }
    }
    if (!known.empty() && !known.count(sensor))
      errors.add(line_number, m.sensor, "sensor " + std::to_string(sensor) + " is not in --sensors");
    if (track < 0)
      errors.add(line_number, m.track, "expected a track number >= 0, found " + std::to_string(track));
    if (truth < -1)
      errors.add(line_number, m.truth, "expected a target id >= -1, found " + std::to_string(truth));
    if (geodetic) {
      if (!(pos[0] >= -90 && pos[0] <= 90))
        errors.add(line_number, m.lat,
                   "expected a latitude in [-90, 90] degrees, found " + number_text(pos[0]));
      if (!(pos[1] >= -180 && pos[1] <= 360))
        errors.add(line_number, m.lon,
                   "expected a longitude in [-180, 360] degrees, found " + number_text(pos[1]));
      if (errors.count() != before) continue;
      if (!frame) frame.emplace(pos[0], pos[1], m.alt.empty() ? 0.0 : pos[2]);  // the first report
      const std::array<double, 3> enu =
          frame->enu(pos[0], pos[1], m.alt.empty() ? frame->origin_alt_m() : pos[2]);
      for (int c = 0; c < sd; ++c) pos[c] = enu[c];
      if (!(std::isfinite(pos[0]) && std::isfinite(pos[1]) && std::isfinite(pos[2])))
        errors.add(line_number, m.alt.empty() ? m.lat : m.alt, "the ENU position is not finite");
    }
    if (errors.count() != before) continue;
    // Covariance: packed columns, or a diagonal of σ columns and the σ flags.
    if (!has_cov) {
      std::fill(cov, cov + p, 0.0);
      bool missing = false;
      for (int c = 0; c < d && !missing; ++c) {
        if (!sigma_given[c]) {
          const std::optional<double> s = (c < sd ? o.sigma_position : o.sigma_velocity).for_sensor(sensor);
          if (!s) {
            missing = true;  // named once per sensor
            if (sensors_without_sigma.insert(sensor).second)
              errors.add_line(line_number, "sensor " + std::to_string(sensor) + " has no σ for " +
                                               (c < sd ? "position" : "velocity") +
                                               " (no covariance or sigma column): give " +
                                               (c < sd ? "--sigma-pos" : "--sigma-vel") +
                                               " or map a sigma column");
            break;
          }
          sigma[c] = *s;
          assumed[sensor][c] = true;
        }
        cov[packed_index(d, c, c)] = sigma[c] * sigma[c];
      }
      if (missing) continue;
    }
    {
      bool finite = true;
      for (int k = 0; k < p; ++k) finite = finite && std::isfinite(cov[k]);
      const std::string why = finite ? track_validation::positive_definite_failure(cov, d) : "";
      const std::string what =
          !finite ? "the covariance is not finite" : "the covariance is not positive definite: " + why;
      if (!finite || !why.empty()) {
        if (has_cov)
          errors.add(line_number, m.cov.front() + "'..'" + m.cov.back(), what);
        else
          errors.add_line(line_number, what + " (a diagonal of σ² from the σ columns and flags)");
        continue;
      }
    }
    // Time order within the local track: backwards or repeated is an error.
    auto [it, inserted] = track_index.emplace(track_key(sensor, track), tracks.size());
    if (inserted) tracks.push_back({sensor, track, time, line_number, {}});
    TrackRows& tr = tracks[it->second];
    if (!inserted && time < tr.last_t) {
      errors.add(line_number, m.time,
                 "time " + number_text(time) + " is before the previous report of sensor " +
                     std::to_string(sensor) + ", track " + std::to_string(track) +
                     " (t = " + number_text(tr.last_t) + " at line " + std::to_string(tr.last_line) +
                     "); time goes backwards within a track");
      continue;
    }
    if (!inserted && time == tr.last_t) {
      errors.add(line_number, m.time,
                 "sensor " + std::to_string(sensor) + ", track " + std::to_string(track) +
                     ", t = " + number_text(time) + " is also line " + std::to_string(tr.last_line) +
                     " (a duplicate report)");
      continue;
    }
    tr.last_t = time;
    tr.last_line = line_number;
    tr.rows.push_back(t.size());
    t.sensor.push_back(sensor);
    t.track.push_back(track);
    t.t.push_back(time);
    t.truth.push_back(truth);
    for (int c = 0; c < sd; ++c) t.state[c].push_back(pos[c]);
    for (int c = 0; c < sd; ++c) t.state[sd + c].push_back(has_velocity ? vel[c] : 0.0);
    for (int k = 0; k < p; ++k) t.cov[k].push_back(cov[k]);
  }
  if (in.bad()) throw InputError(source + ": read error after line " + std::to_string(line_number));
  errors.throw_if_any();
  if (t.size() == 0) throw InputError(source + ": no data rows after the header (line 1)");

  if (!has_velocity)
    for (const TrackRows& tr : tracks)
      if (auto bad = estimate_track_velocity(t, tr.rows))
        throw InputError(source + ": sensor " + std::to_string(tr.sensor) + ", track " +
                         std::to_string(tr.track) + ": the estimated velocity at t = " +
                         number_text(t.t[*bad]) + " is not finite (reports too close in time)");

  // /sensors: the given list, or every id of the file, with its period.
  std::vector<int32_t> ids = o.sensors;
  if (ids.empty()) {
    std::set<int32_t> in_file(t.sensor.begin(), t.sensor.end());
    ids.assign(in_file.begin(), in_file.end());
  }
  std::map<int32_t, std::vector<double>> intervals;
  for (const TrackRows& tr : tracks)
    for (std::size_t k = 1; k < tr.rows.size(); ++k)
      intervals[tr.sensor].push_back(t.t[tr.rows[k]] - t.t[tr.rows[k - 1]]);
  nlohmann::json periods = nlohmann::json::object();
  for (int32_t s : ids) {
    Sensor sensor;
    sensor.id = s;
    sensor.sigma_range = sensor.sigma_bearing = sensor.sigma_elevation = 0.0;
    const std::optional<double> given = o.period.for_sensor(s);
    sensor.period = given ? *given : median_interval(intervals[s]);
    if (!(sensor.period > 0))
      throw InputError(source + ": sensor " + std::to_string(s) +
                       ": no track of it reports twice, so its period cannot be estimated; give --period " +
                       std::to_string(s) + ":SECONDS");
    periods[std::to_string(s)] = {{"period_s", sensor.period},
                                  {"source", given ? "given" : "median interval between reports"}};
    file.sensors.push_back(sensor);
  }

  // What was assumed, for RecordingInfo::import_json.
  nlohmann::json assumed_json = nlohmann::json::object();
  for (const auto& [s, components] : assumed) {
    nlohmann::json e = nlohmann::json::object();
    if (std::any_of(components.begin(), components.begin() + sd, [](bool b) { return b; }))
      e["position_m"] = *o.sigma_position.for_sensor(s);
    if (std::any_of(components.begin() + sd, components.begin() + d, [](bool b) { return b; }))
      e["velocity_m_s"] = *o.sigma_velocity.for_sensor(s);
    assumed_json[std::to_string(s)] = e;
  }
  CsvImportSummary sum;
  sum.rows = t.size();
  sum.tracks = tracks.size();
  sum.velocity = has_velocity ? "columns" : "estimated (three-point derivative per track)";
  sum.covariance = has_cov           ? "columns"
                   : assumed.empty() ? "sigma columns"
                   : m.sigma.empty() ? "assumed (--sigma-pos/--sigma-vel)"
                                     : "sigma columns and assumed (--sigma-pos/--sigma-vel)";
  nlohmann::json info = {{"source", source},
                         {"rows", sum.rows},
                         {"columns", nlohmann::json::parse(csv_mapping_to_json(m))},
                         {"velocity", sum.velocity},
                         {"covariance", sum.covariance},
                         {"assumed_sigma", assumed_json},
                         {"sensors", periods}};
  if (frame) {
    file.recording.frame = "ENU";
    file.recording.frame_origin =
        std::array<double, 3>{frame->origin_lat_deg(), frame->origin_lon_deg(), frame->origin_alt_m()};
    info["position"] =
        "WGS-84 lat, lon" + std::string(m.alt.empty() ? "" : ", alt") + " -> ENU at frame_origin";
  }
  file.recording.import_json = info.dump();
  file.recording.sensors_unknown =
      "position,sigma_range,sigma_bearing,sigma_elevation,offset,p_detect,clutter_rate,reliability";
  if (summary) *summary = sum;
  return file;
}

TrackFile import_csv_tracks_file(const std::string& path, const CsvImportOptions& options,
                                 CsvImportSummary* summary) {
  std::vector<char> buffer(1 << 20);
  std::ifstream in;
  in.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));  // before open
  in.open(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the CSV file for reading");
  return import_csv_tracks(in, path, options, summary);
}

}  // namespace trackassoc
