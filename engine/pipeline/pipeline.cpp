#include "engine/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "engine/pipeline/tuple_decoding.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {}  // namespace

void PipelineOptions::validate() const {
  require(sensors.empty() || sensors.size() >= 2, "PipelineOptions.sensors",
          "expected no sensor ids or at least 2, got " + std::to_string(sensors.size()));
  for (std::size_t a = 0; a < sensors.size(); ++a)
    for (std::size_t b = a + 1; b < sensors.size(); ++b)
      require(sensors[a] != sensors[b], "PipelineOptions.sensors",
              "sensor id " + std::to_string(sensors[a]) + " is given twice");
  require(std::isfinite(common_period) && common_period >= 0.0, "PipelineOptions.common_period",
          "must be finite and >= 0, got " + std::to_string(common_period));
  alignment.validate();
  statistic.validate();
  cost.validate();
}

PipelineOptions PipelineOptions::paper() {
  PipelineOptions o;
  o.span_union = false;
  o.alignment.method = AlignmentMethod::kForward;
  o.alignment.process_noise = 1.0;
  o.statistic.gate = GateMethod::kChiSquareSum;
  o.statistic.link = LinkCost::kPerIndependentScan;  // λ − χ²(n·D): the S-D cost of seed 004 §2
  o.cost.form = CostForm::kChain;                    // seed 000 Eq. 3
  return o;
}

nlohmann::json PipelineOptions::to_json() const {
  return {{"sensors", sensors},
          {"common_period", common_period},
          {"common_span", span_union ? "union" : "intersection"},
          {"alignment", enum_name(alignment.method)},
          {"gate", enum_name(statistic.gate)},
          {"cap_probability", statistic.cap_probability},
          {"scans_per_independent", statistic.scans_per_independent},
          {"process_noise", alignment.process_noise},
          {"max_extrapolation", alignment.max_extrapolation},
          {"extent_sigma", alignment.extent_sigma},
          {"correlated", statistic.correlated},
          {"cross_correlation", statistic.cross_correlation},
          {"common_process_noise", statistic.common_process_noise},
          {"gate_probability", statistic.gate_probability},
          {"link_cost", statistic.link == LinkCost::kPerScan ? "per-scan" : "per-independent-scan"},
          {"cost_form", enum_name(cost.form)},
          {"gated_pair_cost", cost.gated_pair_cost}};
}

std::vector<double> common_time_grid(const TrackTable& tracks, std::span<const int32_t> sensor_ids,
                                     double period, bool span_union) {
  const std::size_t S = sensor_ids.size();
  std::vector<double> first(S, std::numeric_limits<double>::infinity()),
      last(S, -std::numeric_limits<double>::infinity());
  for (std::size_t r = 0; r < tracks.size(); ++r)
    for (std::size_t d = 0; d < S; ++d)
      if (tracks.sensor[r] == sensor_ids[d]) {
        first[d] = std::min(first[d], tracks.t[r]);
        last[d] = std::max(last[d], tracks.t[r]);
      }
  for (std::size_t d = 0; d < S; ++d)
    if (!std::isfinite(first[d]))
      throw InputError("/tracks: sensor " + std::to_string(sensor_ids[d]) +
                       " has no local tracks; the default pipeline (no --3d, --sd or --sparse, solver " +
                       "lr+ls, lr or exact) associates around such a sensor");
  const double start = span_union ? *std::min_element(first.begin(), first.end())
                                  : *std::max_element(first.begin(), first.end()) + period;
  const double end =
      span_union ? *std::max_element(last.begin(), last.end()) : *std::min_element(last.begin(), last.end());
  // The grid and the tracks aligned to it (per track and time: state, covariance, flag) are
  // allocated by the caller: check them against the memory budget before the first push_back.
  const double points = std::floor((end - start) / period) + 1.0;
  std::set<std::pair<int32_t, int32_t>> local_tracks;
  for (std::size_t r = 0; r < tracks.size(); ++r)
    if (std::find(sensor_ids.begin(), sensor_ids.end(), tracks.sensor[r]) != sensor_ids.end())
      local_tracks.emplace(tracks.sensor[r], tracks.track[r]);
  const std::size_t D = static_cast<std::size_t>(tracks.dim());
  char what[200];
  std::snprintf(what, sizeof what,
                "the common time grid (%.4g times of period %g s over [%g, %g] s, %zu local tracks aligned "
                "to it; see --common-period)",
                points, period, start, end, local_tracks.size());
  require_memory(bytes_of(points * static_cast<double>(1 + local_tracks.size()), 8 * (1 + D + D * D)), what);
  std::vector<double> grid;
  const double eps = 1e-9 * std::max(1.0, std::fabs(end));
  for (int64_t k = 0;; ++k) {
    const double t = start + static_cast<double>(k) * period;
    if (t > end + eps) break;
    grid.push_back(t);
  }
  if (grid.empty()) {
    std::string ids;
    for (std::size_t d = 0; d < S; ++d) ids += (d ? ", " : "") + std::to_string(sensor_ids[d]);
    throw InputError("/tracks: sensors " + ids + " never report at a common time (common interval [" +
                     std::to_string(start) + ", " + std::to_string(end) + "] s with period " +
                     std::to_string(period) + " s)");
  }
  return grid;
}

SensorSelection select_sensors(const TrackFile& file, const PipelineOptions& options) {
  SensorSelection sel;
  sel.num_sensors = static_cast<int32_t>(file.sensors.size());
  if (sel.num_sensors < 3)
    throw InputError("/sensors: three-sensor association needs at least 3 sensors, the file has " +
                     std::to_string(sel.num_sensors));
  std::map<int32_t, int32_t> column;
  for (int32_t s = 0; s < sel.num_sensors; ++s) column[file.sensors[s].id] = s;
  if (!options.sensors.empty() && options.sensors.size() != 3)
    throw InputError("--sensors: the 3-D pipeline takes exactly 3 sensor ids, got " +
                     std::to_string(options.sensors.size()) + "; " + std::to_string(options.sensors.size()) +
                     " sensors use the S-D formulation (associate --sd, engine/pipeline/pipeline_sd.hpp)");
  if (options.sensors.empty() && sel.num_sensors > 3)
    throw InputError("/sensors: the file has " + std::to_string(sel.num_sensors) +
                     " sensors and the 3-D pipeline takes three; give --sensors A,B,C, or associate them "
                     "all with the default pipeline (no --solver, or --solver lr+ls|lr|exact)");
  sel.period = options.common_period;
  for (int d = 0; d < 3; ++d) {
    sel.ids[d] = options.sensors.empty() ? file.sensors[d].id : options.sensors[d];
    auto it = column.find(sel.ids[d]);
    if (it == column.end())
      throw InputError("--sensors: sensor id " + std::to_string(sel.ids[d]) + " is not in /sensors/id");
    sel.columns[d] = it->second;
    if (options.common_period == 0.0) sel.period = std::max(sel.period, file.sensors[it->second].period);
  }
  require(sel.period > 0.0, "PipelineOptions.common_period", "the sensors' periods are not positive");
  return sel;
}

AssociationProblem build_association_problem(const TrackFile& file, const PipelineOptions& options) {
  options.validate();
  AssociationProblem p;
  const SensorSelection sel = select_sensors(file, options);
  p.num_sensors = sel.num_sensors;
  p.sensor_ids = sel.ids;
  p.sensor_columns = sel.columns;
  const double period = sel.period;

  const auto t0 = std::chrono::steady_clock::now();
  p.common_times = common_time_grid(file.tracks, p.sensor_ids, period, options.span_union);
  for (int d = 0; d < 3; ++d)
    p.aligned[d] = align_tracks(file.tracks, p.sensor_ids[d], p.common_times, options.alignment);
  p.s12 = independent_sequential_statistic(p.aligned[0], p.aligned[1], options.statistic);
  p.s23 = independent_sequential_statistic(p.aligned[1], p.aligned[2], options.statistic);
  p.s13 = independent_sequential_statistic(p.aligned[0], p.aligned[2], options.statistic);
  p.statistics_time_s = seconds_since(t0);

  set_cost_tensor(p, options.cost);
  return p;
}

void set_cost_tensor(AssociationProblem& p, const CostTensorOptions& cost) {
  const auto t1 = std::chrono::steady_clock::now();
  p.tensor = build_cost_tensor(p.s12, p.s23, cost.form == CostForm::kAllPairs ? &p.s13 : nullptr, cost);
  p.tensor_time_s = seconds_since(t1);
}

void append_output_row(int32_t num_sensors, const std::array<int32_t, 3>& columns,
                       const std::array<AlignedTracks, 3>& aligned, const Tuple3& t,
                       std::array<bool, 3> members, double cost, std::vector<int32_t>& rows,
                       std::vector<double>& costs) {
  std::vector<int32_t> row(num_sensors, kNoTrack);
  bool any = false;
  for (int d = 0; d < 3; ++d)
    if (members[d] && t[d] >= 0) {
      row[columns[d]] = aligned[d].track[t[d]];
      any = true;
    }
  if (!any) return;
  rows.insert(rows.end(), row.begin(), row.end());
  costs.push_back(cost);
}

namespace {

// λ of a gated-in pair of the dense problem, NaN outside the gate (tuple_decoding.hpp).
double dense_gated_lambda(const AssociationProblem& p, int q, int32_t a, int32_t b) {
  const PairStatistic& s = q == 0 ? p.s12 : (q == 1 ? p.s23 : p.s13);
  const std::size_t x = static_cast<std::size_t>(a) * s.n_b + b;
  return s.in_gate[x] ? s.lambda[x] : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::string record_options_json(const nlohmann::json& solver_options, const nlohmann::json& pipeline_json,
                                const nlohmann::json& extra) {
  nlohmann::json opts = {{"solver", solver_options.is_null() ? nlohmann::json::object() : solver_options},
                         {"pipeline", pipeline_json}};
  opts.update(extra);
  return opts.dump();
}

AssociationRecord record_from_summary(const std::string& solver, int32_t num_sensors, uint64_t seed,
                                      const nlohmann::json& solver_options,
                                      const nlohmann::json& pipeline_json, const SolverSummary& summary,
                                      double runtime_s, const nlohmann::json& extra) {
  AssociationRecord rec;
  rec.name = solver;
  rec.num_sensors = num_sensors;
  rec.solver = solver;
  rec.seed = seed;
  rec.options_json = record_options_json(solver_options, pipeline_json, extra);
  rec.objective = summary.objective;
  rec.lower_bound = summary.lower_bound;
  rec.gap = summary.gap;
  rec.termination = termination_name(summary.termination);
  rec.runtime_s = runtime_s;
  return rec;
}

AssociationRecord solve_association(const AssociationProblem& p, const std::string& solver,
                                    const nlohmann::json& solver_options, uint64_t seed,
                                    const PipelineOptions& options) {
  const SolverEntry& entry = find_solver(solver);
  const auto t0 = std::chrono::steady_clock::now();
  Solution3 solution = entry.solve(p.tensor, solver_options, seed);
  const double solve_time = seconds_since(t0);

  AssociationRecord rec = record_from_summary(solver, p.num_sensors, seed, solver_options, options.to_json(),
                                              solution.summary, solve_time);
  rec.energy_rows = solution.energy_rows;
  rec.energy_cols = solution.energy_cols;
  rec.energy = std::move(solution.energy_trace);
  rec.restarts = std::move(solution.restarts);

  // Decoding (engine/pipeline/tuple_decoding.hpp): split every solver tuple into gated-in parts, then pair
  // the tracks left over or unused by ascending gated-in λ.
  const bool all_pairs = options.cost.form == CostForm::kAllPairs;
  const GatedLambda lambda = [&](int q, int32_t a, int32_t b) { return dense_gated_lambda(p, q, a, b); };
  const EmitTuple emit = [&](const std::array<int32_t, 3>& t, double cost) {
    append_output_row(p.num_sensors, p.sensor_columns, p.aligned, t, {true, true, true}, cost, rec.tuples,
                      rec.cost);
  };
  std::array<std::vector<char>, 3> seen;
  for (int d = 0; d < 3; ++d) seen[d].assign(p.aligned[d].n_tracks(), 0);
  std::array<std::vector<int32_t>, 3> left_over;
  for (const Tuple3& t : solution.tuples) {
    for (int d = 0; d < 3; ++d)
      if (t[d] >= 0) seen[d][t[d]] = 1;
    split_tuple(
        lambda, t, all_pairs, [&](double, double, double) { return p.tensor.at(t[0], t[1], t[2]); }, emit,
        left_over);
  }
  for (int d = 0; d < 3; ++d)
    for (int32_t i = 0; i < p.aligned[d].n_tracks(); ++i)
      if (!seen[d][i]) left_over[d].push_back(i);
  pair_leftovers(lambda, left_over, emit);
  return rec;
}

}  // namespace trackassoc
