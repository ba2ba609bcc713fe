// `associate --solver siamese` on a track file (see siamese_track_file.hpp).
#include "engine/pipeline/siamese_track_file.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "engine/solvers/option_fields.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void SiameseTrackFileOptions::validate() const {
  require(sensors.empty() || sensors.size() == 2, "--options: sensors",
          "expected two /sensors ids, got " + std::to_string(sensors.size()));
  require(sensors.size() != 2 || sensors[0] != sensors[1], "--options: sensors",
          "expected two different /sensors ids");
  require(std::isfinite(time_origin), "--options: time_origin", "expected a finite number [s]");
  require(association.probability_threshold > 0 && association.probability_threshold < 1,
          "--options: threshold", "expected a probability in (0, 1)");
  require(association.batch_tracks >= 1, "--options: batch_tracks", "expected >= 1");
}

const OptionFields<SiameseTrackFileOptions>& siamese_track_file_option_fields() {
  using O = SiameseTrackFileOptions;
  static const OptionFields<O> fields{{
      {"sensors", "two /sensors ids", "the two sensors (default: the first two of /sensors)",
       [](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
         auto id = [](const nlohmann::json& x) {
           return x.is_number_integer() && (x.is_number_unsigned() ? in_limits<int32_t>(x.get<uint64_t>())
                                                                   : in_limits<int32_t>(x.get<int64_t>()));
         };
         if (!v.is_array() || v.size() != 2 || !id(v[0]) || !id(v[1]))
           throw InputError("solver '" + solver + "' options: '" + key +
                            "' must be two /sensors ids (int32), e.g. [0, 1]");
         o.sensors = {v[0].get<int32_t>(), v[1].get<int32_t>()};
       },
       [](const O& o) -> std::optional<nlohmann::json> { return o.sensors; }},
      field("points", &O::points, "", "the points of a track: its position estimates, or its plots"),
      field("threshold", path(&O::association, &SiameseAssociationOptions::probability_threshold), "(0, 1)",
            "p_min of the LAP (seed 003)"),
      field("time_origin", &O::time_origin, "finite", "[s], subtracted from every time"),
      field("batch_tracks", path(&O::association, &SiameseAssociationOptions::batch_tracks), ">= 1",
            "tracks per embedding batch (one TBB task)"),
  }};
  return fields;
}

nlohmann::json SiameseTrackFileOptions::to_json() const {
  return siamese_track_file_option_fields().write(*this);
}

SiameseTrackFileOptions siamese_track_file_options(const nlohmann::json& j) {
  SiameseTrackFileOptions o;
  siamese_track_file_option_fields().read(j, o, "siamese");
  o.validate();
  return o;
}

bool inside_training_domain(const TrackNormalisation& n, double x, double y, double t) {
  const double xs = (x - n.x0) / n.position_scale, ys = (y - n.y0) / n.position_scale;
  const double ts = (t - n.t0) / n.time_scale;
  return std::abs(xs) <= 1.6 && std::abs(ys) <= 1.6 && ts >= -0.05 && ts <= 1.05;
}

SiameseTrackFileResult associate_siamese_tracks(const TrackFile& file, const SiameseModel<float>& model,
                                                const SiameseTrackFileOptions& options,
                                                const std::string& name) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  const std::size_t S = file.sensors.size();
  require(S >= 2, "/sensors", "the siamese solver associates two sensors; the file has " + std::to_string(S));
  // The two sensors: their columns in /sensors order.
  int32_t column[2] = {0, 1};
  for (int k = 0; k < 2 && !options.sensors.empty(); ++k) {
    column[k] = -1;
    for (std::size_t s = 0; s < S; ++s)
      if (file.sensors[s].id == options.sensors[k]) column[k] = static_cast<int32_t>(s);
    require(column[k] >= 0, "--options: sensors",
            "no sensor with id " + std::to_string(options.sensors[k]) + " in /sensors");
  }

  SiameseTrackFileResult res;
  const PacketTable p = make_packets(file.tracks, file.sensors, 0.0, options.points,
                                     file.measurements ? &*file.measurements : nullptr);
  // Local tracks of each of the two sensors, by local track number; their points in time order.
  std::vector<int32_t> locals[2];
  std::vector<int32_t> local_sensor(p.num_local(), -1);
  for (std::size_t l = 0; l < p.num_local(); ++l)
    for (int k = 0; k < 2; ++k)
      if (p.local_sensor_id[l] == file.sensors[column[k]].id) {
        locals[k].push_back(static_cast<int32_t>(l));
        local_sensor[l] = k;
      }
  std::vector<std::vector<std::size_t>> rows(p.num_local());
  for (std::size_t i = 0; i < p.size(); ++i)
    if (local_sensor[p.local[i]] >= 0) rows[p.local[i]].push_back(i);
  TrackSequences seq[2];
  std::vector<int32_t> embedded[2];  // dense local index of each sequence
  for (int k = 0; k < 2; ++k) {
    res.sensor_ids[k] = file.sensors[column[k]].id;
    res.tracks[k] = static_cast<int32_t>(locals[k].size());
    std::sort(locals[k].begin(), locals[k].end(),
              [&](int32_t a, int32_t b) { return p.local_track[a] < p.local_track[b]; });
    for (int32_t l : locals[k]) {
      auto& r = rows[l];
      if (r.empty()) continue;  // no point (plot mode: never detected)
      std::stable_sort(r.begin(), r.end(), [&](std::size_t a, std::size_t b) { return p.t[a] < p.t[b]; });
      for (std::size_t i : r) {
        const double t = p.t[i] - options.time_origin;
        seq[k].x.push_back(p.x[i]);
        seq[k].y.push_back(p.y[i]);
        seq[k].t.push_back(t);
        if (!inside_training_domain(model.normalisation, p.x[i], p.y[i], t)) ++res.points_outside_domain;
      }
      seq[k].offset.push_back(static_cast<int64_t>(seq[k].x.size()));
      embedded[k].push_back(l);
    }
    res.points += static_cast<int64_t>(seq[k].x.size());
  }

  res.association = associate_siamese(model, seq[0], seq[1], options.association);
  const SiameseAssociationResult& a = res.association;

  AssociationRecord& rec = res.record;
  rec.name = name;
  rec.num_sensors = static_cast<int32_t>(S);
  rec.solver = "siamese";
  rec.options_json = options.to_json().dump();
  const double log_min = std::log(options.association.probability_threshold);
  std::vector<uint8_t> paired(p.num_local(), 0);
  auto push = [&](int32_t l1, int32_t l2, double cost) {
    std::vector<int32_t> row(S, -1);
    if (l1 >= 0) row[column[0]] = p.local_track[l1];
    if (l2 >= 0) row[column[1]] = p.local_track[l2];
    rec.tuples.insert(rec.tuples.end(), row.begin(), row.end());
    rec.cost.push_back(cost);
  };
  const int32_t n2 = seq[1].size();
  int32_t pairs = 0;
  for (std::size_t i = 0; i < a.left_to_right.size(); ++i) {
    const int32_t j = a.left_to_right[i];
    if (j < 0) continue;
    const double prob = a.probability[i * static_cast<std::size_t>(n2) + static_cast<std::size_t>(j)];
    const int32_t l1 = embedded[0][i], l2 = embedded[1][j];
    push(l1, l2, log_min - std::log(prob));
    paired[l1] = paired[l2] = 1;
    ++pairs;
  }
  for (int k = 0; k < 2; ++k)
    for (int32_t l : locals[k])
      if (!paired[l]) push(k == 0 ? l : -1, k == 1 ? l : -1, 0.0);
  rec.objective = std::accumulate(rec.cost.begin(), rec.cost.end(), 0.0);
  rec.runtime_s = seconds_since(start);
  rec.termination = "embedded " + std::to_string(seq[0].size() + seq[1].size()) + " tracks once, scored " +
                    std::to_string(a.pairs_scored) + " pairs, LAP kept " + std::to_string(pairs) +
                    " pairs at p >= " + std::to_string(options.association.probability_threshold);
  return res;
}

}  // namespace trackassoc
