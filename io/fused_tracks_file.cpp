// /fused/<name>/ groups (io/fused_tracks_file.hpp): writer, reader and validation.
#include "io/fused_tracks_file.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "io/hdf5_columns.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/track_file.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using h5::Group;

const std::set<std::string>& rule_names() {
  static const std::set<std::string> names{"naive", "bsc", "ci"};
  return names;
}

}  // namespace

void check_fused_tracks(const std::string& file, const FusedTrackRecord& r,
                        const std::vector<Sensor>& sensors,
                        const std::vector<AssociationRecord>& associations, StateLayout tracks_layout) {
  const std::string where = file + ": /fused/" + r.name;
  track_validation::check_object_name(file, "/fused", r.name);
  require(rule_names().count(r.rule) > 0, where + " attribute rule",
          "expected \"naive\", \"bsc\" or \"ci\", found \"" + r.rule + "\"");
  require(r.rule == "ci" ? (r.ci_criterion == "trace" || r.ci_criterion == "det") : r.ci_criterion.empty(),
          where + " attribute ci_criterion",
          r.rule == "ci" ? "expected \"trace\" or \"det\", found \"" + r.ci_criterion + "\""
                         : "must be empty unless rule is \"ci\", found \"" + r.ci_criterion + "\"");
  require(
      r.cross_covariance == "none" || r.cross_covariance == "common-process-noise" ||
          r.cross_covariance == "correlation",
      where + " attribute cross_covariance",
      "expected \"none\", \"common-process-noise\" or \"correlation\", found \"" + r.cross_covariance + "\"");
  require(r.layout == tracks_layout, where + " attribute state_layout",
          std::string("expected \"") + layout_name(tracks_layout) + "\" (as /tracks), found \"" +
              layout_name(r.layout) + "\"");
  const int32_t S = static_cast<int32_t>(sensors.size());
  require(r.num_sensors == S, where + "/tuples",
          "expected " + std::to_string(S) + " columns (one per /sensors entry), found " +
              std::to_string(r.num_sensors));
  const AssociationRecord* assoc = nullptr;
  for (const auto& a : associations)
    if (a.name == r.association) assoc = &a;
  require(assoc != nullptr, where + " attribute association",
          "\"" + r.association + "\" is not an /associations group of the file");
  require(assoc->tuples == r.tuples, where + "/tuples",
          "differ from /associations/" + r.association +
              "/tuples: the association was replaced after it was fused; run `trackassoc fuse` again");
  const std::size_t n = r.size(), K = r.num_tuples();
  const int D = state_dim(r.layout), P = packed_size(D);
  require(r.tuple.size() == n && r.sources.size() == n && r.truth.size() == n, where,
          "tuple, t, sources and truth must have the same length (" + std::to_string(n) + ")");
  require(r.state.size() == static_cast<std::size_t>(D) && r.cov.size() == static_cast<std::size_t>(P), where,
          "state and cov columns do not match state_layout");
  for (const auto& c : r.state)
    require(c.size() == n, where + "/state", "expected " + std::to_string(n) + " rows");
  for (const auto& c : r.cov)
    require(c.size() == n, where + "/cov", "expected " + std::to_string(n) + " rows");
  const bool ci = r.rule == "ci";
  require(r.omega.size() == (ci ? n * S : 0), where + "/omega",
          ci ? "expected " + std::to_string(n) + "x" + std::to_string(S) + " weights"
             : "present without rule ci");
  std::vector<double> packed(P);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string row = "row " + std::to_string(i) + ": ";
    require(r.tuple[i] >= 0 && static_cast<std::size_t>(r.tuple[i]) < K, where + "/tuple",
            row + "expected a row of tuples in [0, " + std::to_string(K) + "), found " +
                std::to_string(r.tuple[i]));
    bool finite = std::isfinite(r.t[i]);
    for (const auto& c : r.state) finite = finite && std::isfinite(c[i]);
    require(finite, where, row + "t and state must be finite");
    if (i > 0 && r.tuple[i] == r.tuple[i - 1])
      require(r.t[i] > r.t[i - 1], where + "/t", row + "times must increase strictly within a tuple");
    if (i > 0) require(r.tuple[i] >= r.tuple[i - 1], where + "/tuple", row + "rows must be ordered by tuple");
    require(r.sources[i] >= 2 && r.sources[i] <= S, where + "/sources",
            row + "expected 2.." + std::to_string(S) + ", found " + std::to_string(r.sources[i]));
    require(r.truth[i] >= -1, where + "/truth", row + "expected >= -1, found " + std::to_string(r.truth[i]));
    for (int p = 0; p < P; ++p) packed[p] = r.cov[p][i];
    const std::string why = track_validation::positive_definite_failure(packed.data(), D);
    require(why.empty(), where + "/cov", row + "not positive definite: " + why);
    if (ci) {
      double sum = 0.0;
      for (int32_t s = 0; s < S; ++s) {
        const double w = r.omega[i * S + s];
        require(std::isfinite(w) && w >= 0.0 && w <= 1.0, where + "/omega",
                row + "weights must be in [0, 1]");
        sum += w;
      }
      require(std::fabs(sum - 1.0) <= 1e-6, where + "/omega",
              row + "weights sum to " + std::to_string(sum) + ", not 1");
    }
  }
  const bool evaluated = !r.sensor_position_rmse.empty() || !r.sensor_position_rmse_rows.empty();
  if (evaluated)
    require(r.sensor_position_rmse.size() == static_cast<std::size_t>(S) &&
                r.sensor_position_rmse_rows.size() == static_cast<std::size_t>(S),
            where + "/sensor_position_rmse", "expected one entry per sensor (" + std::to_string(S) + ")");
}

void write_fused_tracks(const Group& root, const std::vector<FusedTrackRecord>& records) {
  if (records.empty()) return;
  const Group parent = root.create_group("fused", /*track_order=*/true);
  for (const auto& r : records) {
    const Group g = parent.create_group(r.name);
    g.write_attribute("association", r.association);
    g.write_attribute("rule", r.rule);
    g.write_attribute("ci_criterion", r.ci_criterion);
    g.write_attribute("cross_covariance", r.cross_covariance);
    g.write_attribute("options", r.options_json);
    g.write_attribute("state_layout", std::string(layout_name(r.layout)));
    const std::size_t n = r.size(), S = static_cast<std::size_t>(r.num_sensors);
    g.write_dataset("tuples", std::span<const int32_t>(r.tuples), {r.num_tuples(), S});
    g.write_dataset("tuple", std::span<const int32_t>(r.tuple), {n});
    g.write_dataset("t", std::span<const double>(r.t), {n});
    const std::vector<double> state = h5::rows_from_columns(r.state, n);
    g.write_dataset("state", std::span<const double>(state), {n, r.state.size()});
    const std::vector<double> cov = h5::rows_from_columns(r.cov, n);
    g.write_dataset("cov", std::span<const double>(cov), {n, r.cov.size()});
    g.write_dataset("sources", std::span<const int32_t>(r.sources), {n});
    g.write_dataset("truth", std::span<const int32_t>(r.truth), {n});
    if (!r.omega.empty()) g.write_dataset("omega", std::span<const double>(r.omega), {n, S});
    if (!std::isnan(r.position_rmse)) {
      g.write_attribute("position_rmse", r.position_rmse);
      g.write_attribute("position_rmse_rows", r.position_rmse_rows);
    }
    if (!r.sensor_position_rmse.empty()) {
      g.write_dataset("sensor_position_rmse", std::span<const double>(r.sensor_position_rmse), {S});
      g.write_dataset("sensor_position_rmse_rows", std::span<const int32_t>(r.sensor_position_rmse_rows),
                      {S});
    }
  }
}

std::vector<FusedTrackRecord> read_fused_tracks(const Group& root, const std::string& file) {
  std::vector<FusedTrackRecord> out;
  if (!root.has("fused")) return out;
  const Group parent = root.open_group("fused");
  for (const std::string& name : parent.children()) {
    const Group g = parent.open_group(name);
    FusedTrackRecord r;
    r.name = name;
    for (const char* attr : {"association", "rule", "state_layout"})
      if (!g.has_attribute(attr)) g.fail(attr, "missing attribute (required)");
    r.association = g.read_string_attribute("association");
    r.rule = g.read_string_attribute("rule");
    if (g.has_attribute("ci_criterion")) r.ci_criterion = g.read_string_attribute("ci_criterion");
    if (g.has_attribute("cross_covariance")) r.cross_covariance = g.read_string_attribute("cross_covariance");
    if (g.has_attribute("options")) r.options_json = g.read_string_attribute("options");
    r.layout = h5::read_layout(g, file);
    const std::size_t D = state_dim(r.layout), P = packed_size(static_cast<int>(D));
    std::vector<hsize_t> dims;
    const std::vector<int64_t> tuples = g.read_integers("tuples", 2, dims);
    r.num_sensors = static_cast<int32_t>(std::min<hsize_t>(dims[1], 1 << 20));
    r.tuples.assign(tuples.begin(), tuples.end());  // compared with the association's, which is range-checked
    for (int64_t v : tuples)
      if (v < -1 || v > std::numeric_limits<int32_t>::max())
        g.fail("tuples", "value " + std::to_string(v) + " out of range");
    const std::size_t n = g.table_rows({"tuple", "t", "state", "cov", "sources", "truth", "omega"});
    const std::string ref = g.child_path("tuple");
    r.tuple = h5::read_int32_column(g, "tuple", n, ref);
    r.t = h5::read_1d(g, "t", n, ref);
    r.state = h5::columns_from_rows(
        h5::read_table_2d(g, "state", n, D, "rows as tuple, columns as state_layout"), n, D);
    r.cov = h5::columns_from_rows(
        h5::read_table_2d(g, "cov", n, P, "rows as tuple, D(D+1)/2 packed upper-triangle columns"), n, P);
    r.sources = h5::read_int32_column(g, "sources", n, ref);
    r.truth = h5::read_int32_column(g, "truth", n, ref);
    if (g.has("omega"))
      r.omega = h5::read_table_2d(g, "omega", n, r.num_sensors, "rows as tuple, one column per sensor");
    if (g.has_attribute("position_rmse")) {
      r.position_rmse = g.read_double_attribute("position_rmse");
      r.position_rmse_rows = static_cast<int32_t>(g.read_integer_attribute("position_rmse_rows"));
    }
    if (g.has("sensor_position_rmse")) {
      r.sensor_position_rmse = h5::read_1d(g, "sensor_position_rmse", r.num_sensors, "one per sensor");
      r.sensor_position_rmse_rows =
          h5::read_int32_column(g, "sensor_position_rmse_rows", r.num_sensors, "one per sensor");
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace trackassoc
