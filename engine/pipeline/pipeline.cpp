#include "engine/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "engine/pipeline/pair_source.hpp"
#include "engine/pipeline/tuple_decoding.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
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

AssociationProblem build_association_problem(const TrackFile& file, const PipelineOptions& options) {
  options.validate();
  AssociationProblem p;
  const auto t0 = std::chrono::steady_clock::now();
  static_cast<AlignedSensors&>(p) = align_sensors(file, options, SensorRule::kThree);
  p.stages.push_back(stage_since("alignment", t0));
  const auto t1 = std::chrono::steady_clock::now();
  p.s12 = all_pairs_statistic(p, 0, 1, options.statistic);  // the dense pair source (pair_source.hpp)
  p.s23 = all_pairs_statistic(p, 1, 2, options.statistic);
  p.s13 = all_pairs_statistic(p, 0, 2, options.statistic);
  p.stages.push_back(stage_since("statistics", t1));

  set_cost_tensor(p, options.cost);
  return p;
}

void set_cost_tensor(AssociationProblem& p, const CostTensorOptions& cost) {
  const auto t1 = std::chrono::steady_clock::now();
  p.tensor = build_cost_tensor(p.s12, p.s23, cost.form == CostForm::kAllPairs ? &p.s13 : nullptr, cost);
  std::erase_if(p.stages, [](const StageReport& r) { return r.name == "tensor"; });  // rebuilt
  p.stages.push_back(stage_since("tensor", t1, sizeof(float) * double(p.tensor.size()) / 1048576.0));
}

void append_output_row(const AlignedSensors& sensors, const Tuple3& t, double cost,
                       std::vector<int32_t>& rows, std::vector<double>& costs) {
  std::vector<int32_t> row(sensors.file_sensors, kNoTrack);
  bool any = false;
  for (int d = 0; d < 3; ++d)
    if (t[d] >= 0) {
      row[sensors.sensor_columns[d]] = sensors.aligned[d].track[t[d]];
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

  AssociationRecord rec = record_from_summary(solver, p.file_sensors, seed, solver_options, options.to_json(),
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
    append_output_row(p, t, cost, rec.tuples, rec.cost);
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

namespace {

// Distinct local tracks of each selected sensor: the dense tensor's n1, n2, n3.
std::array<std::size_t, 3> dense_track_counts(const TrackFile& file, const PipelineOptions& options) {
  const SensorSelection sel = select_sensors(file, options, SensorRule::kThree);
  std::set<int32_t> tracks[3];
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    for (int d = 0; d < 3; ++d)
      if (file.tracks.sensor[r] == sel.ids[d]) tracks[d].insert(file.tracks.track[r]);
  return {tracks[0].size(), tracks[1].size(), tracks[2].size()};
}

double tensor_bytes(const std::array<std::size_t, 3>& n) {
  return static_cast<double>(sizeof(float)) * static_cast<double>(n[0]) * static_cast<double>(n[1]) *
         static_cast<double>(n[2]);
}

}  // namespace

void require_dense_tensor_fits(const TrackFile& file, const PipelineOptions& options) {
  const auto n = dense_track_counts(file, options);
  const double bytes = tensor_bytes(n);
  const double budget = static_cast<double>(options.cost.memory_budget_bytes);
  if (bytes <= budget) return;
  char text[400];
  std::snprintf(text, sizeof text,
                "the dense %zux%zux%zu cost tensor needs %.4g MiB, over the memory budget of %.4g MiB "
                "(--memory-budget); rerun with --sparse (gated candidate tuples, solved per connected "
                "component), or raise --memory-budget",
                n[0], n[1], n[2], bytes / 1048576.0, budget / 1048576.0);
  throw InputError(text);
}

}  // namespace trackassoc
