#include "engine/pipeline/fuzzy_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "kernels/core/error.hpp"
#include "kernels/filters/kalman_converted.hpp"

namespace trackassoc {

void FuzzyPipelineOptions::validate() const {
  require(std::isfinite(packet_period) && packet_period >= 0, "packet_period", "expected >= 0 [s]");
  if (method == FusionMethod::kFuzzy)
    fuzzy.validate();
  else
    ftaa.validate();
}

namespace {

using O = FuzzyPipelineOptions;

const OptionFields<AlphaBetaOptions>& smoother_fields() {
  using A = AlphaBetaOptions;
  static const OptionFields<A> fields{{
      field("gains", &A::gains, "", "Kalata steady-state gains from σ_w, σ_v, or fixed α, β"),
      field("alpha", &A::alpha, "(0, 2)", "fixed gains: α"),
      field("beta", &A::beta, "(0, 4 − 2α)", "fixed gains: β"),
      field("process_noise", &A::process_noise, "> 0", "Kalata gains: σ_w [m/s²]"),
      field("measurement_noise", &A::measurement_noise, "> 0", "Kalata gains: σ_v [m]"),
  }};
  return fields;
}

// The keys of both methods; `m` is the method's own options (fuzzy or ftaa).
template <class M>
std::vector<OptionField<O>> common_fields(M O::*m) {
  return {
      {"method", "the solver's name", "as written in the options attribute; must be the solver's own name",
       [](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
         if (!v.is_string() || v.get<std::string>() != enum_name(o.method))
           throw InputError("solver '" + solver + "' options: '" + key + "' must be \"" +
                            enum_name(o.method) + "\", the solver's own name");
       },
       [](const O& o) -> std::optional<nlohmann::json> { return enum_name(o.method); }},
      field("packet_period", &O::packet_period, ">= 0",
            "[s] one packet per local track and period; 0 = every row"),
      field("packets", &O::packet_source, "", "a packet is a /tracks row's position, or its plot"),
      field("u_max_position", path(m, &M::scales, &FactorScales::position), "> 0",
            "u_max of Eq. 5, position [m]"),
      field("u_max_speed", path(m, &M::scales, &FactorScales::speed), "> 0", "u_max of Eq. 5, speed [m/s]"),
      field("u_max_heading", path(m, &M::scales, &FactorScales::heading), "> 0",
            "u_max of Eq. 5, heading [rad]"),
      field("synthesis", path(m, &M::synthesis, &SynthesisOptions::function), "", "synthesis function"),
      field("weights", path(m, &M::synthesis, &SynthesisOptions::weights), "3 numbers >= 0, sum 1",
            "a_l of Eq. 11–12"),
      field("q", path(m, &M::synthesis, &SynthesisOptions::q), "> 0", "exponent of Eq. 9 and 12"),
      field("gate", path(m, &M::gate), "> 0", "[m] gate on the position difference u1"),
      field("track_timeout", path(m, &M::track_timeout), ">= 0",
            "[s] drop a track silent for longer; 0 = never"),
  };
}

const OptionFields<O>& fuzzy_fields() {
  using F = FuzzyAssociationOptions;
  static const OptionFields<O> fields{[] {
    auto f = common_fields(&O::fuzzy);
    f.push_back(field("weighting", path(&O::fuzzy, &F::weighting), "", "reliability weighting of μ"));
    f.push_back(
        field("min_degree", path(&O::fuzzy, &F::min_degree), "[0, 1]", "μ below this never associates"));
    f.push_back(object_field("smoother", path(&O::fuzzy, &F::smoother), smoother_fields(),
                             "alpha-beta smoother of the system tracks"));
    return f;
  }()};
  return fields;
}

const OptionFields<O>& ftaa_fields() {
  using F = FtaaOptions;
  static const OptionFields<O> fields{[] {
    auto f = common_fields(&O::ftaa);
    f.push_back(
        field("threshold", path(&O::ftaa, &F::threshold), "[0, 1]", "a scan succeeds when S >= this"));
    f.push_back(field("association_quality", path(&O::ftaa, &F::association_quality), ">= 1",
                      "M: consecutive successes to associate"));
    f.push_back(field("separation_quality", path(&O::ftaa, &F::separation_quality), ">= 1",
                      "D_max: consecutive failures to separate"));
    return f;
  }()};
  return fields;
}

}  // namespace

const OptionFields<FuzzyPipelineOptions>& fuzzy_pipeline_option_fields(FusionMethod method) {
  return method == FusionMethod::kFuzzy ? fuzzy_fields() : ftaa_fields();
}

nlohmann::json FuzzyPipelineOptions::to_json() const {
  return fuzzy_pipeline_option_fields(method).write(*this);
}

FuzzyPipelineOptions fuzzy_pipeline_options(FusionMethod method, const nlohmann::json& j) {
  FuzzyPipelineOptions o;
  o.method = method;
  fuzzy_pipeline_option_fields(method).read(j, o, enum_name(method));
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
  st.method = enum_name(options.method);
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
  a.solver = enum_name(options.method);
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
  std::erase_if(file.fused, [&](const FusedTrackRecord& r) { return r.association == name; });  // stale now
  file.associations.push_back(res.association);
  file.system_tracks.push_back(res.system_tracks);
  return res;
}

}  // namespace trackassoc
