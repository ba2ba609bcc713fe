// Schema v1 reader and writer (io/track_file.hpp, docs/design.md §3).
//
// Reading is lenient where a recorded track set from elsewhere cannot be expected to carry
// something (every /sensors dataset but id, /tracks/truth, the summary attributes of an
// association) and strict everywhere else: dtype classes, shapes, finiteness, ids and positive
// definite covariances (io/track_validation.hpp).
#include "io/track_file.hpp"

#include <limits>
#include <map>
#include <set>

#include "io/atomic_file.hpp"
#include "io/hdf5_columns.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/isolated_run.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

namespace tv = track_validation;
using h5::columns_from_rows;
using h5::Group;
using h5::read_1d;
using h5::read_layout;
using h5::rows_from_columns;
using h5::shape_text;
constexpr auto read_int32 = h5::read_int32_column;
constexpr auto read_2d = h5::read_table_2d;

constexpr const char* kFormat = "trackassoc";
constexpr int32_t kSchemaVersion = 1;

// ---------------------------------------------------------------- writing helpers

template <typename T>
void write_1d(const Group& g, const std::string& name, const std::vector<T>& v) {
  g.write_dataset(name, std::span<const T>(v), {v.size()});
}

void write_sensors(const Group& root, const std::vector<Sensor>& sensors, const RecordingInfo& info) {
  const Group g = root.create_group("sensors");
  if (!info.sensors_unknown.empty()) g.write_attribute("unknown", info.sensors_unknown);
  const std::size_t n = sensors.size();
  std::vector<int32_t> id(n);
  std::vector<double> position(n * 3);
  std::vector<std::vector<double>> fields(8, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Sensor& s = sensors[i];
    id[i] = s.id;
    for (int c = 0; c < 3; ++c) position[i * 3 + c] = s.position[c];
    const double values[] = {s.sigma_range, s.sigma_bearing, s.sigma_elevation, s.period,
                             s.offset,      s.p_detect,      s.clutter_rate,    s.reliability};
    for (int f = 0; f < 8; ++f) fields[f][i] = values[f];
  }
  write_1d(g, "id", id);
  g.write_dataset("position", std::span<const double>(position), {n, 3});
  const char* names[] = {"sigma_range", "sigma_bearing", "sigma_elevation", "period",
                         "offset",      "p_detect",      "clutter_rate",    "reliability"};
  for (int f = 0; f < 8; ++f) write_1d(g, names[f], fields[f]);
}

void write_tracks(const Group& root, const TrackTable& t, const RecordingInfo& info) {
  const Group g = root.create_group("tracks");
  const std::size_t n = t.size();
  const std::size_t d = t.dim(), p = packed_size(t.dim());
  g.write_attribute("state_layout", std::string(layout_name(t.layout)));
  if (!info.frame.empty()) g.write_attribute("frame", info.frame);
  if (info.frame_origin) {
    g.write_attribute("frame_origin_lat_deg", (*info.frame_origin)[0]);
    g.write_attribute("frame_origin_lon_deg", (*info.frame_origin)[1]);
    g.write_attribute("frame_origin_alt_m", (*info.frame_origin)[2]);
  }
  if (!info.import_json.empty()) g.write_attribute("import", info.import_json);
  write_1d(g, "sensor", t.sensor);
  write_1d(g, "track", t.track);
  write_1d(g, "t", t.t);
  {  // one row-major copy at a time
    const std::vector<double> state = rows_from_columns(t.state, n);
    g.write_dataset("state", std::span<const double>(state), {n, d});
  }
  const std::vector<double> cov = rows_from_columns(t.cov, n);
  g.write_dataset("cov", std::span<const double>(cov), {n, p});
  write_1d(g, "truth", t.truth);
}

void write_truth(const Group& root, const TruthTable& t) {
  const Group g = root.create_group("truth");
  const std::size_t n = t.size();
  g.write_attribute("state_layout", std::string(layout_name(t.layout)));
  write_1d(g, "target", t.target);
  write_1d(g, "t", t.t);
  const std::vector<double> state = rows_from_columns(t.state, n);
  g.write_dataset("state", std::span<const double>(state),
                  {n, static_cast<std::size_t>(state_dim(t.layout))});
}

void write_measurements(const Group& root, const Measurements& m) {
  const Group g = root.create_group("measurements");
  write_1d(g, "sensor", m.sensor);
  write_1d(g, "t", m.t);
  write_1d(g, "range", m.range);
  write_1d(g, "bearing", m.bearing);
  write_1d(g, "elevation", m.elevation);
  write_1d(g, "target", m.target);
}

void write_restarts(const Group& parent, const RestartTable& t) {
  const Group g = parent.create_group("restarts");
  write_1d(g, "restart", t.restart);
  write_1d(g, "valid_raw", t.valid_raw);
  write_1d(g, "sweeps", t.sweeps);
  write_1d(g, "mean_field_steps", t.mean_field_steps);
  write_1d(g, "energy", t.energy);
  write_1d(g, "repaired_objective", t.repaired_objective);
  write_1d(g, "objective", t.objective);
}

void write_association(const Group& parent, const AssociationRecord& a) {
  const Group g = parent.create_group(a.name);
  const std::size_t k = a.cost.size(), s = static_cast<std::size_t>(a.num_sensors);
  g.write_dataset("tuples", std::span<const int32_t>(a.tuples), {k, s});
  write_1d(g, "cost", a.cost);
  g.write_attribute("solver", a.solver);
  g.write_attribute("options", a.options_json);
  g.write_attribute("objective", a.objective);
  g.write_attribute("lower_bound", a.lower_bound);
  g.write_attribute("gap", a.gap);
  g.write_attribute("runtime_s", a.runtime_s);
  g.write_attribute("seed", a.seed);
  g.write_attribute("termination", a.termination);
  if (!a.energy.empty() || a.energy_rows > 0)
    g.write_dataset("energy", std::span<const float>(a.energy),
                    {static_cast<hsize_t>(a.energy_rows), static_cast<hsize_t>(a.energy_cols)});
  if (a.restarts.size() > 0) write_restarts(g, a.restarts);
  if (!a.unassociated.empty())
    g.write_dataset("unassociated", std::span<const int32_t>(a.unassociated), {a.unassociated.size() / 2, 2});
  if (!a.target.empty()) g.write_dataset("target", std::span<const int32_t>(a.target), {a.target.size()});
}

void write_metrics(const Group& parent, const MetricsRecord& m) {
  const Group g = parent.create_group(m.name);
  g.write_attribute("correct_rate", m.correct_rate);
  g.write_attribute("false_rate", m.false_rate);
  g.write_attribute("missed_rate", m.missed_rate);
  for (const auto& [name, values] : m.tables) write_1d(g, name, values);
}

// ---------------------------------------------------------------- reading helpers

std::vector<Sensor> read_sensors(const Group& root) {
  const Group g = root.open_group("sensors");
  g.table_rows({"id", "position", "sigma_range", "sigma_bearing", "sigma_elevation", "period", "offset",
                "p_detect", "clutter_rate", "reliability"});
  const std::vector<int32_t> id = read_int32(g, "id", 0, "");
  const std::size_t n = id.size();
  std::vector<Sensor> sensors(n);
  for (std::size_t i = 0; i < n; ++i) sensors[i].id = id[i];
  if (g.has("position")) {
    const std::vector<double> p = read_2d(g, "position", n, 3, "one x,y,z row per sensor");
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) sensors[i].position[c] = p[i * 3 + c];
  }
  struct Field {
    const char* name;
    double Sensor::*member;
  };
  const Field fields[] = {{"sigma_range", &Sensor::sigma_range},
                          {"sigma_bearing", &Sensor::sigma_bearing},
                          {"sigma_elevation", &Sensor::sigma_elevation},
                          {"period", &Sensor::period},
                          {"offset", &Sensor::offset},
                          {"p_detect", &Sensor::p_detect},
                          {"clutter_rate", &Sensor::clutter_rate},
                          {"reliability", &Sensor::reliability}};
  for (const Field& f : fields) {
    if (!g.has(f.name)) continue;  // optional: the Sensor default stands
    const std::vector<double> v = read_1d(g, f.name, n, "/sensors/id");
    for (std::size_t i = 0; i < n; ++i) sensors[i].*f.member = v[i];
  }
  return sensors;
}

// The optional attributes of RecordingInfo; a file without them gives the empty RecordingInfo.
RecordingInfo read_recording_info(const Group& root) {
  RecordingInfo info;
  const Group tracks = root.open_group("tracks");
  if (tracks.has_attribute("frame")) info.frame = tracks.read_string_attribute("frame");
  if (tracks.has_attribute("frame_origin_lat_deg"))
    info.frame_origin = std::array<double, 3>{tracks.read_double_attribute("frame_origin_lat_deg"),
                                              tracks.read_double_attribute("frame_origin_lon_deg"),
                                              tracks.read_double_attribute("frame_origin_alt_m")};
  if (tracks.has_attribute("import")) info.import_json = tracks.read_string_attribute("import");
  const Group sensors = root.open_group("sensors");
  if (sensors.has_attribute("unknown")) info.sensors_unknown = sensors.read_string_attribute("unknown");
  return info;
}

TrackTable read_tracks(const Group& root, const std::string& file) {
  const Group g = root.open_group("tracks");
  TrackTable t(read_layout(g, file));
  g.table_rows({"sensor", "track", "t", "state", "cov", "truth"});
  const std::size_t d = t.dim(), p = packed_size(t.dim());
  t.sensor = read_int32(g, "sensor", 0, "");
  const std::size_t n = t.sensor.size();
  t.track = read_int32(g, "track", n, "/tracks/sensor");
  t.t = read_1d(g, "t", n, "/tracks/sensor");
  t.state =
      columns_from_rows(read_2d(g, "state", n, d, "rows as /tracks/sensor, columns as state_layout"), n, d);
  t.cov = columns_from_rows(
      read_2d(g, "cov", n, p,
              "rows as /tracks/sensor, D(D+1)/2 = " + std::to_string(p) + " packed upper-triangle columns"),
      n, p);
  t.truth = g.has("truth") ? read_int32(g, "truth", n, "/tracks/sensor") : std::vector<int32_t>(n, -1);
  return t;
}

TruthTable read_truth(const Group& root, const std::string& file) {
  const Group g = root.open_group("truth");
  g.table_rows({"target", "t", "state"});
  std::vector<int32_t> target = read_int32(g, "target", 0, "");
  const std::size_t n = target.size();
  // The layout attribute is optional here: without it, D from the shape of state decides.
  StateLayout layout = StateLayout::kXY_VXVY;
  if (g.has_attribute("state_layout")) {
    layout = read_layout(g, file);
  } else {
    const std::vector<hsize_t> shape = g.dataset_shape("state");
    if (shape.size() == 2 && shape[1] == 6) layout = StateLayout::kXYZ_VXVYVZ;
  }
  TruthTable t(layout);
  t.target = std::move(target);
  t.t = read_1d(g, "t", n, "/truth/target");
  const std::size_t d = state_dim(layout);
  t.state = columns_from_rows(read_2d(g, "state", n, d, "rows as /truth/target, columns as the state layout"),
                              n, d);
  return t;
}

Measurements read_measurements(const Group& root) {
  const Group g = root.open_group("measurements");
  g.table_rows({"sensor", "t", "range", "bearing", "target"});
  Measurements m;
  m.sensor = read_int32(g, "sensor", 0, "");
  const std::size_t n = m.sensor.size();
  const std::string ref = "/measurements/sensor";
  m.t = read_1d(g, "t", n, ref);
  m.range = read_1d(g, "range", n, ref);
  m.bearing = read_1d(g, "bearing", n, ref);
  if (g.has("elevation")) {
    std::vector<hsize_t> dims;
    m.elevation = g.read_doubles("elevation", 1, dims);
    if (dims[0] != 0 && dims[0] != n)
      g.fail("elevation", "expected " + std::to_string(n) + " rows (as " + ref + ") or 0 (2-D), found " +
                              std::to_string(dims[0]));
  }
  m.target = g.has("target") ? read_int32(g, "target", n, ref) : std::vector<int32_t>(n, -1);
  return m;
}

RestartTable read_restarts(const Group& g) {
  RestartTable t;
  g.table_rows(
      {"restart", "valid_raw", "sweeps", "mean_field_steps", "energy", "repaired_objective", "objective"});
  t.restart = read_int32(g, "restart", 0, "");
  const std::size_t n = t.restart.size();
  const std::string ref = g.child_path("restart");
  t.valid_raw = read_int32(g, "valid_raw", n, ref);
  t.sweeps = read_int32(g, "sweeps", n, ref);
  t.mean_field_steps = read_int32(g, "mean_field_steps", n, ref);
  t.energy = read_1d(g, "energy", n, ref);
  t.repaired_objective = read_1d(g, "repaired_objective", n, ref);
  t.objective = read_1d(g, "objective", n, ref);
  return t;
}

AssociationRecord read_association(const Group& parent, const std::string& name) {
  const Group g = parent.open_group(name);
  AssociationRecord a;
  a.name = name;
  g.table_rows({"tuples", "cost"});
  std::vector<hsize_t> dims;
  const std::vector<int64_t> tuples = g.read_integers("tuples", 2, dims);
  const std::size_t k = dims[0];
  a.num_sensors = static_cast<int32_t>(std::min<hsize_t>(dims[1], std::numeric_limits<int32_t>::max()));
  a.tuples.resize(tuples.size());
  for (std::size_t i = 0; i < tuples.size(); ++i) {
    if (tuples[i] < -1 || tuples[i] > std::numeric_limits<int32_t>::max())
      g.fail("tuples", "row " + std::to_string(i / std::max<hsize_t>(dims[1], 1)) +
                           ": expected -1 or a local track number, found " + std::to_string(tuples[i]));
    a.tuples[i] = static_cast<int32_t>(tuples[i]);
  }
  a.cost = read_1d(g, "cost", k, g.child_path("tuples") + " rows");
  if (g.has_attribute("solver")) a.solver = g.read_string_attribute("solver");
  if (g.has_attribute("options")) a.options_json = g.read_string_attribute("options");
  if (g.has_attribute("termination")) a.termination = g.read_string_attribute("termination");
  if (g.has_attribute("objective")) a.objective = g.read_double_attribute("objective");
  if (g.has_attribute("lower_bound")) a.lower_bound = g.read_double_attribute("lower_bound");
  if (g.has_attribute("gap")) a.gap = g.read_double_attribute("gap");
  if (g.has_attribute("runtime_s")) a.runtime_s = g.read_double_attribute("runtime_s");
  if (g.has_attribute("seed")) a.seed = g.read_unsigned_attribute("seed");
  if (g.has("energy")) {
    std::vector<hsize_t> e;
    a.energy = g.read_floats("energy", 2, e);
    if (e[0] > static_cast<hsize_t>(std::numeric_limits<int32_t>::max()) ||
        e[1] > static_cast<hsize_t>(std::numeric_limits<int32_t>::max()))
      g.fail("energy", "shape " + shape_text(e) + " too large");
    a.energy_rows = static_cast<int32_t>(e[0]);
    a.energy_cols = static_cast<int32_t>(e[1]);
  }
  if (g.has("restarts")) a.restarts = read_restarts(g.open_group("restarts"));
  if (g.has("unassociated")) {
    std::vector<hsize_t> u;
    const std::vector<int64_t> rows = g.read_integers("unassociated", 2, u);
    if (u[1] != 2) g.fail("unassociated", "expected 2 columns (sensor id, track), found " + shape_text(u));
    a.unassociated.reserve(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i] < std::numeric_limits<int32_t>::min() || rows[i] > std::numeric_limits<int32_t>::max())
        g.fail("unassociated", "row " + std::to_string(i / 2) + ": " + std::to_string(rows[i]) +
                                   " is not an int32 sensor id or track number");
      a.unassociated.push_back(static_cast<int32_t>(rows[i]));
    }
  }
  if (g.has("target")) {
    std::vector<hsize_t> d;
    const std::vector<int64_t> target = g.read_integers("target", 1, d);
    if (d[0] != k)
      g.fail("target", "expected one entry per tuple (" + std::to_string(k) + "), found " + shape_text(d));
    std::map<std::pair<std::size_t, int32_t>, int64_t> target_of;  // (column, track) → target
    for (std::size_t i = 0; i < k; ++i) {
      if (target[i] < 0 || target[i] > std::numeric_limits<int32_t>::max())
        g.fail("target", "row " + std::to_string(i) + ": expected a target number >= 0, found " +
                             std::to_string(target[i]));
      for (std::size_t c = 0; c < dims[1]; ++c) {
        const int32_t track = a.tuples[i * dims[1] + c];
        if (track < 0) continue;
        auto [it, fresh] = target_of.emplace(std::make_pair(c, track), target[i]);
        if (!fresh && it->second != target[i])
          g.fail("target", "row " + std::to_string(i) + ": track " + std::to_string(track) + " of column " +
                               std::to_string(c) + " is in targets " + std::to_string(it->second) + " and " +
                               std::to_string(target[i]));
      }
      a.target.push_back(static_cast<int32_t>(target[i]));
    }
  }
  return a;
}

MetricsRecord read_metrics(const Group& parent, const std::string& name) {
  const Group g = parent.open_group(name);
  MetricsRecord m;
  m.name = name;
  m.correct_rate = g.read_double_attribute("correct_rate");
  m.false_rate = g.read_double_attribute("false_rate");
  m.missed_rate = g.read_double_attribute("missed_rate");
  for (const std::string& table : g.children()) {
    std::vector<hsize_t> dims;
    m.tables[table] = g.read_doubles(table, 1, dims);
  }
  return m;
}

}  // namespace

TrackFile read_track_file(const std::string& path, double timeout_s) {
  if (timeout_s <= 0) timeout_s = isolated_read_timeout(path);
  run_isolated(
      path, [&] { read_track_file_in_process(path); }, timeout_s);
  return read_track_file_in_process(path);
}

TrackFile read_track_file_in_process(const std::string& path) {
  h5::File f = h5::File::open_read_only(path);
  const Group root = f.root();
  if (!root.has_attribute("format"))
    throw InputError(path + ": not a trackassoc file (the root has no 'format' attribute)");
  const std::string format = root.read_string_attribute("format");
  if (format != kFormat)
    throw InputError(path + ": / attribute format: expected \"trackassoc\", found \"" + format + "\"");
  const int64_t version = root.read_integer_attribute("schema_version");
  if (version != kSchemaVersion)
    throw InputError(path + ": / attribute schema_version: expected 1, found " + std::to_string(version) +
                     " (this build reads schema v1)");

  // The checks of values (io/track_validation.hpp) are pure computation on what was read: the
  // isolated child, there to exercise the library, leaves them to the parent's read of the same file
  // (they are a third of a large file's read: widearea's 6.2 M rows).
  const bool check = !in_isolated_child();
  TrackFile file;
  file.created_by = root.has_attribute("created_by") ? root.read_string_attribute("created_by") : "";
  file.scenario_json = root.has_attribute("scenario") ? root.read_string_attribute("scenario") : "";
  if (!root.has("sensors")) throw InputError(path + ": /sensors: missing group (required)");
  if (!root.has("tracks")) throw InputError(path + ": /tracks: missing group (required)");
  file.sensors = read_sensors(root);
  if (check) tv::check_sensors(path, file.sensors);
  file.tracks = read_tracks(root, path);
  if (root.open_group("tracks").has("source_track"))
    file.source_track =
        h5::read_int32_column(root.open_group("tracks"), "source_track", file.tracks.size(), "/tracks/t");
  if (check) tv::check_tracks(path, file.tracks, file.sensors);
  file.recording = read_recording_info(root);
  if (check) tv::check_recording_info(path, file.recording);
  if (root.has("truth")) {
    file.truth = read_truth(root, path);
    if (check) tv::check_truth(path, *file.truth);
  }
  if (root.has("measurements")) {
    file.measurements = read_measurements(root);
    if (check) tv::check_measurements(path, *file.measurements, file.sensors);
  }
  if (root.has("associations")) {
    const Group g = root.open_group("associations");
    for (const std::string& name : g.children()) {
      file.associations.push_back(read_association(g, name));
      if (check) tv::check_association(path, file.associations.back(), file.sensors, file.tracks);
    }
  }
  if (root.has("metrics")) {
    const Group g = root.open_group("metrics");
    for (const std::string& name : g.children()) file.metrics.push_back(read_metrics(g, name));
  }
  file.system_tracks = read_system_tracks(root);
  if (check)
    for (const auto& r : file.system_tracks) check_system_tracks(path, r, file.sensors);
  file.registration = read_registration(root, path);
  file.fused = read_fused_tracks(root, path);
  if (check)
    for (const auto& r : file.fused)
      check_fused_tracks(path, r, file.sensors, file.associations, file.tracks.layout);
  return file;
}

namespace {

void write_track_file_with(const std::string& path, const TrackFile& file,
                           const TrackModelProbabilities* model_prob) {
  if (model_prob && model_prob->prob.size() != file.tracks.size() * std::size_t(model_prob->num_models))
    throw InputError(path + ": /tracks/model_prob: " + std::to_string(model_prob->prob.size()) +
                     " values for " + std::to_string(file.tracks.size()) + " rows of " +
                     std::to_string(model_prob->num_models) + " models");
  write_atomically(path, [&](const std::string& tmp) {
    // Messages name the file the user asked for, not the temporary one.
    tv::check_sensors(path, file.sensors);
    tv::check_tracks(path, file.tracks, file.sensors);
    tv::check_recording_info(path, file.recording);
    std::set<std::string> names;
    for (const auto& a : file.associations) {
      tv::check_association(path, a, file.sensors, file.tracks);
      if (!names.insert(a.name).second)
        throw InputError(path + ": /associations/" + a.name + ": name used twice");
    }
    names.clear();
    for (const auto& r : file.system_tracks) {
      check_system_tracks(path, r, file.sensors);
      if (!names.insert(r.name).second)
        throw InputError(path + ": /system_tracks/" + r.name + ": name used twice");
    }
    names.clear();
    for (const auto& r : file.fused) {
      check_fused_tracks(path, r, file.sensors, file.associations, file.tracks.layout);
      if (!names.insert(r.name).second) throw InputError(path + ": /fused/" + r.name + ": name used twice");
    }
    if (file.registration) check_registration(path, *file.registration, file.sensors.size());
    names.clear();
    for (const auto& m : file.metrics) {
      tv::check_metrics(path, m);
      if (!names.insert(m.name).second) throw InputError(path + ": /metrics/" + m.name + ": name used twice");
    }

    h5::File f = h5::File::create(tmp);
    {
      const Group root = f.root();
      root.write_attribute("format", std::string(kFormat));
      root.write_attribute("schema_version", kSchemaVersion);
      root.write_attribute("created_by", file.created_by);
      root.write_attribute("scenario", file.scenario_json);
      write_sensors(root, file.sensors, file.recording);
      // Truth and measurements are checked as they are written: a bad value found here still
      // leaves `path` untouched (write_atomically removes the temporary file).
      if (file.truth) {
        tv::check_truth(path, *file.truth);
        write_truth(root, *file.truth);
      }
      if (file.measurements) {
        tv::check_measurements(path, *file.measurements, file.sensors);
        write_measurements(root, *file.measurements);
      }
      write_tracks(root, file.tracks, file.recording);
      if (!file.source_track.empty()) {
        if (file.source_track.size() != file.tracks.size())
          throw InputError(path + ": /tracks/source_track: expected " + std::to_string(file.tracks.size()) +
                           " rows (one per /tracks row), found " + std::to_string(file.source_track.size()));
        const hsize_t n = file.tracks.size();
        root.open_group("tracks").write_dataset("source_track", std::span<const int32_t>(file.source_track),
                                                {n});
      }
      if (model_prob) {
        const Group tracks = root.open_group("tracks");
        tracks.write_dataset(
            "model_prob", std::span<const double>(model_prob->prob),
            {static_cast<hsize_t>(file.tracks.size()), static_cast<hsize_t>(model_prob->num_models)});
        tracks.write_attribute("models", model_prob->models);
      }
      if (!file.associations.empty()) {
        const Group g = root.create_group("associations", /*track_order=*/true);
        for (const auto& a : file.associations) write_association(g, a);
      }
      if (!file.metrics.empty()) {
        const Group g = root.create_group("metrics", /*track_order=*/true);
        for (const auto& m : file.metrics) write_metrics(g, m);
      }
      write_system_tracks(root, file.system_tracks);
      write_fused_tracks(root, file.fused);
      write_registration(root, file.registration);
    }
    f.close();
  });
}

}  // namespace

void write_track_file(const std::string& path, const TrackFile& file) {
  write_track_file_with(path, file, nullptr);
}

void write_track_file(const std::string& path, const TrackFile& file,
                      const TrackModelProbabilities& model_prob) {
  write_track_file_with(path, file, &model_prob);
}

}  // namespace trackassoc
