#include "engine/pipeline/result_tables.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <ostream>
#include <ranges>
#include <sstream>

#include "engine/pipeline/associator.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_tracks.hpp"
#include "io/hdf5_wrapper.hpp"

namespace trackassoc {

using h5::File;
using h5::Group;
using h5::shape_text;
using h5::silence_library_errors;

namespace {

// One CSV line at a time, numbers by std::to_chars (the shortest text that reads back exactly).
class CsvRows {
 public:
  CsvRows(std::ostream& out, char delimiter) : out_(out), delimiter_(delimiter) {}
  void header(const std::vector<std::string>& names) {
    for (const auto& n : names) text(n);
    end();
  }
  template <class T>
  void number(T v) {
    sep();
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    line_.append(buf, r.ptr);
  }
  void text(const std::string& s) {
    sep();
    line_ += s;
  }
  void end() {
    line_ += '\n';
    out_ << line_;
    line_.clear();
    first_ = true;
  }

 private:
  void sep() {
    if (!first_) line_ += delimiter_;
    first_ = false;
  }
  std::ostream& out_;
  char delimiter_;
  std::string line_;
  bool first_ = true;
};

// The group named `name` of `records` (empty: the only one), or an InputError naming what the file has.
template <class R>
const R& pick(const std::vector<R>& records, const std::string& name, const std::string& path,
              const std::string& group, const std::string& producer) {
  std::string names;
  const R* found = nullptr;
  for (const R& r : records) {
    names += (names.empty() ? "" : ", ") + r.name;
    if (r.name == name) found = &r;
  }
  if (records.empty())
    throw InputError(path + ": /" + group + " is empty; run `trackassoc " + producer + "` first");
  if (name.empty()) {
    if (records.size() != 1)
      throw InputError("--name: " + path + " has " + std::to_string(records.size()) + " /" + group +
                       " groups (" + names + "); name one");
    return records.front();
  }
  if (!found)
    throw InputError("--name: no /" + group + "/" + name + " in " + path + " (it has " + names + ")");
  return *found;
}

struct TrackSpan {
  double first_t = 0.0, last_t = 0.0;
  int64_t reports = 0, source_track = -1;
};

// (sensor, track) -> its span and source track (/tracks/source_track of its first report when the
// file has that dataset, else the track number).
std::map<std::pair<int32_t, int32_t>, TrackSpan> track_spans(const std::string& path, const TrackFile& file) {
  const TrackTable& t = file.tracks;
  std::vector<int64_t> source;
  {
    silence_library_errors();
    const File f = File::open_read_only(path);
    const Group tracks = f.root().open_group("tracks");
    if (tracks.has("source_track")) {
      std::vector<hsize_t> dims;
      source = tracks.read_integers("source_track", 1, dims);
      if (source.size() != t.size())
        tracks.fail("source_track", "expected " + std::to_string(t.size()) + " rows (as /tracks/t), found " +
                                        std::to_string(source.size()));
    }
  }
  std::map<std::pair<int32_t, int32_t>, TrackSpan> spans;
  for (std::size_t r = 0; r < t.size(); ++r) {
    auto [it, fresh] = spans.try_emplace({t.sensor[r], t.track[r]});
    TrackSpan& s = it->second;
    if (fresh || t.t[r] < s.first_t) {
      s.first_t = t.t[r];
      s.source_track = source.empty() ? t.track[r] : source[r];
    }
    s.last_t = fresh ? t.t[r] : std::max(s.last_t, t.t[r]);
    ++s.reports;
  }
  return spans;
}

ResultTableSummary associations_table(const std::string& path, const TrackFile& file, const std::string& name,
                                      CsvRows& csv) {
  const AssociationRecord& a = pick(file.associations, name, path, "associations", "associate");
  const auto spans = track_spans(path, file);
  csv.header({"target", "tuple", "sensor", "track", "source_track", "cost"});
  ResultTableSummary s{0, "/associations/" + a.name, {}};
  const std::size_t cols = static_cast<std::size_t>(a.num_sensors);
  for (std::size_t k = 0; k < a.num_tuples(); ++k)
    for (std::size_t c = 0; c < cols; ++c) {
      const int32_t track = a.tuples[k * cols + c];
      if (track < 0) continue;
      const int32_t sensor = file.sensors[c].id;
      csv.number(a.target.empty() ? static_cast<int64_t>(k) : a.target[k]);
      csv.number(static_cast<int64_t>(k));
      csv.number(sensor);
      csv.number(track);
      csv.number(spans.at({sensor, track}).source_track);
      csv.number(a.cost[k]);
      csv.end();
      ++s.rows;
    }
  return s;
}

ResultTableSummary unassociated_table(const std::string& path, const TrackFile& file, const std::string& name,
                                      CsvRows& csv) {
  const AssociationRecord& a = pick(file.associations, name, path, "associations", "associate");
  std::vector<std::pair<int32_t, int32_t>> rows;
  if (!a.unassociated.empty()) {
    for (std::size_t i = 0; i + 1 < a.unassociated.size(); i += 2)
      rows.emplace_back(a.unassociated[i], a.unassociated[i + 1]);
  } else {  // a file from before /unassociated: the same rule, from the tuples
    std::vector<int32_t> ids;
    for (const Sensor& sensor : file.sensors) ids.push_back(sensor.id);
    for (const UnassociatedTracks& u : unassociated_tracks(file, ids, a))
      for (int32_t track : u.tracks) rows.emplace_back(u.sensor_id, track);
  }
  const auto spans = track_spans(path, file);
  csv.header({"sensor", "track", "source_track", "first_t", "last_t", "reports"});
  for (const auto& [sensor, track] : rows) {
    const TrackSpan& sp = spans.at({sensor, track});
    csv.number(sensor);
    csv.number(track);
    csv.number(sp.source_track);
    csv.number(sp.first_t);
    csv.number(sp.last_t);
    csv.number(sp.reports);
    csv.end();
  }
  return {rows.size(), "/associations/" + a.name + " (unassociated)", {}};
}

std::vector<std::string> state_names(StateLayout layout) {
  std::vector<std::string> names;
  std::stringstream in(layout_name(layout));
  for (std::string n; std::getline(in, n, ',');) names.push_back(n);
  return names;
}

ResultTableSummary fused_table(const std::string& path, const TrackFile& file, const std::string& name,
                               CsvRows& csv) {
  const FusedTrackRecord& f = pick(file.fused, name, path, "fused", "fuse");
  const std::vector<std::string> names = state_names(f.layout);
  std::vector<std::string> header{"tuple", "t"};
  header.insert(header.end(), names.begin(), names.end());
  for (std::size_t r = 0; r < names.size(); ++r)
    for (std::size_t c = r; c < names.size(); ++c) header.push_back("cov_" + names[r] + "_" + names[c]);
  header.insert(header.end(), {"sources", "truth"});
  csv.header(header);
  for (std::size_t r = 0; r < f.size(); ++r) {
    csv.number(f.tuple[r]);
    csv.number(f.t[r]);
    for (const auto& col : f.state) csv.number(col[r]);
    for (const auto& col : f.cov) csv.number(col[r]);
    csv.number(f.sources[r]);
    csv.number(f.truth[r]);
    csv.end();
  }
  return {f.size(), "/fused/" + f.name, {}};
}

ResultTableSummary registration_table(const std::string& path, const TrackFile& file, CsvRows& csv) {
  silence_library_errors();
  const File f = File::open_read_only(path);
  const Group root = f.root();
  if (!root.has("registration") || !root.is_group("registration"))
    throw InputError(path +
                     ": no /registration group (the file's sensors were not registered); nothing to export");
  const Group reg = root.open_group("registration");
  const std::size_t s = file.sensors.size();
  ResultTableSummary summary{s, "/registration", {}};
  std::vector<std::string> header{"sensor"};
  std::vector<std::vector<double>> columns;  // one per CSV column, s values each
  std::vector<double> ids;                   // the rows' sensor ids: /registration/sensor
  for (const std::size_t i : std::views::iota(std::size_t{0}, s)) ids.push_back(file.sensors[i].id);
  for (const std::string& name : reg.children()) {
    if (reg.is_group(name)) {
      summary.skipped.push_back(name + " (a group)");
      continue;
    }
    const std::vector<hsize_t> shape = reg.dataset_shape(name);
    if (shape.empty() || shape.size() > 3 || shape[0] != s) {
      summary.skipped.push_back(name + " (shape " + shape_text(shape) + ", not one row per sensor)");
      continue;
    }
    std::vector<hsize_t> dims;
    std::vector<double> v;
    try {
      v = reg.read_doubles(name, static_cast<int>(shape.size()), dims);
    } catch (const InputError&) {
      summary.skipped.push_back(name + " (not numeric)");
      continue;
    }
    if (name == "sensor" && shape.size() == 1) {  // the id column itself, not a second "sensor"
      ids = v;
      continue;
    }
    // Columns NAME (S), NAME_j (S × k), NAME_j_l (S × k × m, e.g. each sensor's covariance).
    const std::size_t m = shape.size() == 3 ? shape[2] : 1, k = (shape.size() >= 2 ? shape[1] : 1) * m;
    for (std::size_t j = 0; j < k; ++j) {
      header.push_back(shape.size() == 1 ? name
                       : shape.size() == 2
                           ? name + "_" + std::to_string(j)
                           : name + "_" + std::to_string(j / m) + "_" + std::to_string(j % m));
      std::vector<double> col(s);
      for (std::size_t i = 0; i < s; ++i) col[i] = v[i * k + j];
      columns.push_back(std::move(col));
    }
  }
  csv.header(header);
  for (std::size_t i = 0; i < s; ++i) {
    csv.number(ids[i]);
    for (const auto& col : columns) csv.number(col[i]);
    csv.end();
  }
  return summary;
}

}  // namespace

ResultTableSummary export_result_table(const std::string& path, const TrackFile& file, ResultTable what,
                                       const std::string& name, std::ostream& out, char delimiter) {
  if (!name.empty() && (what == ResultTable::kTracks || what == ResultTable::kRegistration))
    throw InputError("--name: picks an /associations or /fused group; --what " +
                     std::string(enum_name(what)) + " has none");
  CsvRows csv(out, delimiter);
  switch (what) {
    case ResultTable::kTracks:
      export_csv_tracks(file, out, delimiter);
      return {file.tracks.size(), "/tracks", {}};
    case ResultTable::kAssociations:
      return associations_table(path, file, name, csv);
    case ResultTable::kUnassociated:
      return unassociated_table(path, file, name, csv);
    case ResultTable::kFused:
      return fused_table(path, file, name, csv);
    case ResultTable::kRegistration:
      return registration_table(path, file, csv);
  }
  return {};
}

ResultTableSummary write_result_table(const std::string& output, const std::string& path,
                                      const TrackFile& file, ResultTable what, const std::string& name,
                                      char delimiter) {
  ResultTableSummary s;
  write_atomically(output, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(output + ": cannot open for writing");
    s = export_result_table(path, file, what, name, out, delimiter);
    out.close();
    if (!out) throw InputError(output + ": write failed (disk full?)");
  });
  return s;
}

}  // namespace trackassoc
