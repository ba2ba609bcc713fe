#include "engine/fuzzy_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "kernels/error.hpp"
#include "kernels/kalman_converted.hpp"

namespace trackassoc {

FusionMethod parse_fusion_method(const std::string& name) {
  if (name == "fuzzy") return FusionMethod::kFuzzy;
  if (name == "ftaa") return FusionMethod::kFtaa;
  throw InputError("--solver: expected fuzzy or ftaa, got '" + name + "'");
}

const char* fusion_method_name(FusionMethod m) { return m == FusionMethod::kFuzzy ? "fuzzy" : "ftaa"; }

void FuzzyPipelineOptions::validate() const {
  require(std::isfinite(packet_period) && packet_period >= 0, "packet_period", "expected >= 0 [s]");
  if (method == FusionMethod::kFuzzy)
    fuzzy.validate();
  else
    ftaa.validate();
}

nlohmann::json FuzzyPipelineOptions::to_json() const {
  nlohmann::json j;
  j["method"] = fusion_method_name(method);
  j["packet_period"] = packet_period;
  j["packets"] = packet_source == PacketSource::kPlot ? "plot" : "track";
  const FactorScales& sc = method == FusionMethod::kFuzzy ? fuzzy.scales : ftaa.scales;
  const SynthesisOptions& sy = method == FusionMethod::kFuzzy ? fuzzy.synthesis : ftaa.synthesis;
  j["u_max_position"] = sc.position;
  j["u_max_speed"] = sc.speed;
  j["u_max_heading"] = sc.heading;
  j["synthesis"] = synthesis_name(sy.function);
  j["weights"] = sy.weights;
  j["q"] = sy.q;
  if (method == FusionMethod::kFuzzy) {
    j["gate"] = fuzzy.gate;
    j["weighting"] = weighting_name(fuzzy.weighting);
    j["min_degree"] = fuzzy.min_degree;
    j["track_timeout"] = fuzzy.track_timeout;
    const AlphaBetaOptions& ab = fuzzy.smoother;
    j["smoother"] = {{"gains", ab.gains == AlphaBetaGainMode::kKalata ? "kalata" : "fixed"},
                     {"alpha", ab.alpha},
                     {"beta", ab.beta},
                     {"process_noise", ab.process_noise},
                     {"measurement_noise", ab.measurement_noise}};
  } else {
    j["gate"] = ftaa.gate;
    j["threshold"] = ftaa.threshold;
    j["association_quality"] = ftaa.association_quality;
    j["separation_quality"] = ftaa.separation_quality;
    j["track_timeout"] = ftaa.track_timeout;
  }
  return j;
}

namespace {

double number(const nlohmann::json& j, const std::string& key) {
  if (!j.is_number()) throw InputError("--options: key '" + key + "': expected a number, got " + j.dump());
  return j.get<double>();
}

}  // namespace

FuzzyPipelineOptions fuzzy_pipeline_options(FusionMethod method, const nlohmann::json& j) {
  if (!j.is_object()) throw InputError("--options: expected a JSON object");
  FuzzyPipelineOptions o;
  o.method = method;
  const bool fz = method == FusionMethod::kFuzzy;
  FactorScales& sc = fz ? o.fuzzy.scales : o.ftaa.scales;
  SynthesisOptions& sy = fz ? o.fuzzy.synthesis : o.ftaa.synthesis;
  for (const auto& [key, v] : j.items()) {
    if (key == "method") {  // as to_json() writes it, so a stored /associations options attribute reads back
      if (!v.is_string() || v.get<std::string>() != fusion_method_name(method))
        throw InputError(std::string("--options: key 'method': expected \"") + fusion_method_name(method) +
                         "\", the solver's own name");
    } else if (key == "packet_period")
      o.packet_period = number(v, key);
    else if (key == "packets") {
      const std::string src = v.is_string() ? v.get<std::string>() : "";
      if (src != "track" && src != "plot")
        throw InputError("--options: key 'packets': expected \"track\" or \"plot\"");
      o.packet_source = src == "plot" ? PacketSource::kPlot : PacketSource::kTrack;
    } else if (key == "gate")
      (fz ? o.fuzzy.gate : o.ftaa.gate) = number(v, key);
    else if (key == "u_max_position")
      sc.position = number(v, key);
    else if (key == "u_max_speed")
      sc.speed = number(v, key);
    else if (key == "u_max_heading")
      sc.heading = number(v, key);
    else if (key == "q")
      sy.q = number(v, key);
    else if (key == "track_timeout")
      (fz ? o.fuzzy.track_timeout : o.ftaa.track_timeout) = number(v, key);
    else if (key == "synthesis") {
      if (!v.is_string()) throw InputError("--options: key 'synthesis': expected a string");
      sy.function = parse_synthesis(v.get<std::string>());
    } else if (key == "weights") {
      if (!v.is_array()) throw InputError("--options: key 'weights': expected an array of 3 numbers");
      sy.weights.clear();
      for (const auto& w : v) sy.weights.push_back(number(w, key));
    } else if (fz && key == "weighting") {
      if (!v.is_string()) throw InputError("--options: key 'weighting': expected a string");
      o.fuzzy.weighting = parse_weighting(v.get<std::string>());
    } else if (fz && key == "min_degree")
      o.fuzzy.min_degree = number(v, key);
    else if (fz && key == "smoother") {
      if (!v.is_object()) throw InputError("--options: key 'smoother': expected an object");
      AlphaBetaOptions& ab = o.fuzzy.smoother;
      for (const auto& [k2, v2] : v.items()) {
        if (k2 == "gains") {
          const std::string g = v2.is_string() ? v2.get<std::string>() : "";
          if (g != "kalata" && g != "fixed")
            throw InputError("--options: smoother.gains: expected kalata or fixed");
          ab.gains = g == "kalata" ? AlphaBetaGainMode::kKalata : AlphaBetaGainMode::kFixed;
        } else if (k2 == "alpha")
          ab.alpha = number(v2, k2);
        else if (k2 == "beta")
          ab.beta = number(v2, k2);
        else if (k2 == "process_noise")
          ab.process_noise = number(v2, k2);
        else if (k2 == "measurement_noise")
          ab.measurement_noise = number(v2, k2);
        else
          throw InputError("--options: unknown key 'smoother." + k2 + "'");
      }
    } else if (!fz && key == "threshold")
      o.ftaa.threshold = number(v, key);
    else if (!fz && key == "association_quality")
      o.ftaa.association_quality = static_cast<int>(number(v, key));
    else if (!fz && key == "separation_quality")
      o.ftaa.separation_quality = static_cast<int>(number(v, key));
    else
      throw InputError("--options: unknown key '" + key + "' for solver " + fusion_method_name(method));
  }
  o.validate();
  return o;
}

PacketTable make_packets(const TrackTable& tracks, const std::vector<Sensor>& sensors, double packet_period,
                         PacketSource source, const Measurements* measurements) {
  require(!sensors.empty(), "sensors", "expected at least one sensor");
  const bool plots = source == PacketSource::kPlot;
  require(!plots || measurements != nullptr, "packets",
          "\"plot\" packets need /measurements (use \"track\" for a recorded track set)");
  // (sensor, target, time in µs) → measurement row, for plot packets.
  std::map<std::tuple<int32_t, int32_t, int64_t>, std::size_t> plot_of;
  if (plots)
    for (std::size_t m = 0; m < measurements->size(); ++m)
      if (measurements->target[m] >= 0)
        plot_of[{measurements->sensor[m], measurements->target[m], std::llround(measurements->t[m] * 1e6)}] =
            m;
  require(std::isfinite(packet_period) && packet_period >= 0, "packet_period", "expected >= 0 [s]");
  std::map<int32_t, int32_t> sensor_index;
  for (std::size_t s = 0; s < sensors.size(); ++s) sensor_index[sensors[s].id] = static_cast<int32_t>(s);
  std::map<std::pair<int32_t, int32_t>, int32_t> local_index;
  // Rows in time order per local track, for thinning.
  std::vector<std::size_t> order(tracks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return tracks.t[a] < tracks.t[b]; });
  std::vector<uint8_t> keep(tracks.size(), 0);
  std::vector<double> last_kept;
  PacketTable p;
  std::vector<int32_t> row_local(tracks.size());
  for (std::size_t r : order) {
    const auto it = sensor_index.find(tracks.sensor[r]);
    require(it != sensor_index.end(), "/tracks/sensor",
            "row " + std::to_string(r) + ": " + std::to_string(tracks.sensor[r]) + " is not a /sensors id");
    const auto key = std::make_pair(tracks.sensor[r], tracks.track[r]);
    auto [li, inserted] = local_index.emplace(key, static_cast<int32_t>(p.local_track.size()));
    if (inserted) {
      p.local_sensor_id.push_back(key.first);
      p.local_track.push_back(key.second);
      last_kept.push_back(-std::numeric_limits<double>::infinity());
    }
    const int32_t l = li->second;
    row_local[r] = l;
    if (plots) {
      require(r < tracks.truth.size() && tracks.truth[r] >= 0, "/tracks/truth",
              "row " + std::to_string(r) + ": \"plot\" packets need the target of every track row");
      if (!plot_of.count({tracks.sensor[r], tracks.truth[r], std::llround(tracks.t[r] * 1e6)}))
        continue;  // missed
    }
    // 1e-9 s tolerance: report times are sums of periods.
    if (packet_period == 0.0 || tracks.t[r] >= last_kept[l] + packet_period - 1e-9) {
      keep[r] = 1;
      last_kept[l] = tracks.t[r];
    }
  }
  for (std::size_t r = 0; r < tracks.size(); ++r) {
    if (!keep[r]) continue;
    p.sensor.push_back(sensor_index[tracks.sensor[r]]);
    p.local.push_back(row_local[r]);
    p.t.push_back(tracks.t[r]);
    if (plots) {
      const std::size_t m = plot_of.at({tracks.sensor[r], tracks.truth[r], std::llround(tracks.t[r] * 1e6)});
      const ConvertedMeasurement z = convert_polar(2, sensors[sensor_index[tracks.sensor[r]]],
                                                   measurements->range[m], measurements->bearing[m], 0.0);
      p.x.push_back(z.z[0]);
      p.y.push_back(z.z[1]);
    } else {
      p.x.push_back(tracks.state[0][r]);
      p.y.push_back(tracks.state[1][r]);
    }
    p.truth.push_back(r < tracks.truth.size() ? tracks.truth[r] : -1);
  }
  return p;
}

FuzzyPipelineResult run_fuzzy_pipeline(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                       const FuzzyPipelineOptions& options, const std::string& name,
                                       const Measurements* measurements) {
  options.validate();
  FuzzyPipelineResult res;
  res.packets = make_packets(tracks, sensors, options.packet_period, options.packet_source, measurements);
  const PacketTable& p = res.packets;
  const std::size_t L = p.num_local(), S = sensors.size();
  std::vector<double> reliability(S);
  for (std::size_t s = 0; s < S; ++s) reliability[s] = sensors[s].reliability;

  res.fusion = options.method == FusionMethod::kFuzzy
                   ? run_fuzzy_association(p.spans(), reliability, L, options.fuzzy)
                   : run_ftaa(p.spans(), S, L, options.ftaa).fusion;
  const FusionOutput& f = res.fusion;

  // System tracks in processing order.
  SystemTrackRecord& st = res.system_tracks;
  st.name = name;
  st.method = fusion_method_name(options.method);
  st.options_json = options.to_json().dump();
  for (std::size_t i : arrival_order(p.t)) {
    if (f.system_track[i] < 0) continue;
    st.track.push_back(f.system_track[i]);
    st.t.push_back(p.t[i]);
    st.state[0].push_back(f.x[i]);
    st.state[1].push_back(f.y[i]);
    st.state[2].push_back(f.vx[i]);
    st.state[3].push_back(f.vy[i]);
  }
  // Mapping: packets per (local, system) pair.
  std::map<std::pair<int32_t, int32_t>, int32_t> counts;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (f.system_track[i] >= 0) ++counts[{p.local[i], f.system_track[i]}];
  std::vector<int32_t> majority(L, -1), majority_count(L, 0);
  for (const auto& [key, c] : counts) {
    const auto [l, j] = key;
    st.map_sensor.push_back(p.local_sensor_id[l]);
    st.map_local_track.push_back(p.local_track[l]);
    st.map_system_track.push_back(j);
    st.map_packets.push_back(c);
    if (c > majority_count[l]) {  // map order is by system track: ties keep the lower number
      majority_count[l] = c;
      majority[l] = j;
    }
  }

  // Tuples.
  std::vector<int32_t> local_sensor(L, -1);
  for (std::size_t i = 0; i < p.size(); ++i) local_sensor[p.local[i]] = p.sensor[i];
  std::map<int32_t, std::vector<int32_t>> rows;  // system track → tuple (dense local index per sensor)
  std::vector<int32_t> singles;
  for (std::size_t l = 0; l < L; ++l) {
    if (local_sensor[l] < 0) continue;  // all its rows thinned away: impossible, the first is kept
    const int32_t j = majority[l];
    if (j < 0) {
      singles.push_back(static_cast<int32_t>(l));
      continue;
    }
    auto& row = rows.try_emplace(j, std::vector<int32_t>(S, -1)).first->second;
    int32_t& slot = row[local_sensor[l]];
    if (slot < 0) {
      slot = static_cast<int32_t>(l);
    } else {
      ++res.sensor_conflicts;
      const int32_t loser = majority_count[l] > majority_count[slot] ? slot : static_cast<int32_t>(l);
      if (loser == slot) slot = static_cast<int32_t>(l);
      singles.push_back(loser);
    }
  }
  // Mean μ per system track for the tuple cost.
  std::map<int32_t, std::pair<double, int32_t>> mu;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (f.system_track[i] >= 0 && std::isfinite(f.degree[i])) {
      auto& [sum, n] = mu[f.system_track[i]];
      sum += f.degree[i];
      ++n;
    }
  AssociationRecord& a = res.association;
  a.name = name;
  a.num_sensors = static_cast<int32_t>(S);
  a.solver = fusion_method_name(options.method);
  a.options_json = st.options_json;
  auto push = [&](const std::vector<int32_t>& dense, double cost) {
    for (int32_t l : dense) a.tuples.push_back(l < 0 ? -1 : p.local_track[l]);
    a.cost.push_back(cost);
  };
  for (const auto& [j, row] : rows) {
    double cost = 0.0;
    if (options.method == FusionMethod::kFuzzy) {
      const auto it = mu.find(j);
      cost = it == mu.end() ? 1.0 : 1.0 - it->second.first / it->second.second;
    }
    push(row, cost);
  }
  std::sort(singles.begin(), singles.end());
  for (int32_t l : singles) {
    std::vector<int32_t> row(S, -1);
    row[local_sensor[l]] = l;
    push(row, options.method == FusionMethod::kFuzzy ? 1.0 : 0.0);
  }
  a.objective = 0.0;
  for (double c : a.cost) a.objective += c;
  a.runtime_s = f.summary.wall_time_s;
  a.termination = std::string(termination_name(f.summary.termination)) + ": " +
                  std::to_string(f.summary.iterations) + " decisions, " +
                  std::to_string(f.num_system_tracks) + " system tracks";
  if (res.sensor_conflicts > 0)
    a.termination += ", " + std::to_string(res.sensor_conflicts) +
                     " local tracks of a sensor shared a system track with another of the same sensor "
                     "(kept the one with most packets; the others are tuples of their own)";
  return res;
}

FuzzyPipelineResult associate_fuzzy(TrackFile& file, const FuzzyPipelineOptions& options,
                                    const std::string& name) {
  FuzzyPipelineResult res = run_fuzzy_pipeline(file.tracks, file.sensors, options, name,
                                               file.measurements ? &*file.measurements : nullptr);
  std::erase_if(file.associations, [&](const AssociationRecord& a) { return a.name == name; });
  std::erase_if(file.system_tracks, [&](const SystemTrackRecord& r) { return r.name == name; });
  file.associations.push_back(res.association);
  file.system_tracks.push_back(res.system_tracks);
  return res;
}

}  // namespace trackassoc
