#include "engine/jobs/run_job.hpp"

#include <algorithm>
#include <memory>
#include <set>
#include <utility>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/report/association_map.hpp"
#include "engine/report/summary_chart.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// The rows of the default pipeline (what `associate` does without flags), its exact solver, and
// seed 000's gate in the same pipeline.
const std::vector<std::string>& default_rows() {
  static const std::vector<std::string> rows{"default", "default-exact", "default-chi2-gate"};
  return rows;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Every row name is a default row or a registered 3-D solver; every key of solver_options names a
// solver and holds an object; when `strict`, also that the solver is in `solvers` (when given) and
// reads every key of its options.
void check_request(const std::vector<std::string>& solvers, const nlohmann::json& options, bool strict) {
  for (const auto& s : solvers)
    if (!contains(default_rows(), s)) find_solver(s);
  if (!options.is_object())
    throw InputError("--options: expected a JSON object keyed by solver name, got " +
                     options.dump().substr(0, 200));
  std::vector<std::string> names;
  for (const auto& e : solver_registry()) names.push_back(e.name);
  for (auto it = options.begin(); it != options.end(); ++it) {
    const std::string& name = it.key();
    if (!contains(names, name))
      throw InputError(
          "--options: " + unknown_name_message("solver", name, names) +
          " (run's --options is keyed by solver name, e.g. '{\"hopfield\": {\"restarts\": 8}}')");
    if (!it.value().is_object())
      throw InputError("--options: '" + name + "': expected a JSON object of that solver's options, found " +
                       it.value().dump());
    if (!strict) continue;
    if (!solvers.empty() && !contains(solvers, name))
      throw InputError("--options: '" + name + "' has options but is not in --solvers");
    find_solver(name).solve(CostTensor3(1, 1, 1), it.value(), 1);
  }
}

}  // namespace

void RunJobOptions::validate() const {
  check_request(solvers, solver_options, false);
  pipeline.validate();
}

void check_run_solver_options(const nlohmann::json& solver_options, const std::vector<std::string>& solvers) {
  check_request(solvers, solver_options, true);
}

RunJobResult run_main_job(const RunJobOptions& o, const std::function<void(const RunJobResult&)>& on_scene) {
  o.validate();
  const Scenario scenario = load_scenario(o.scenario);
  const SimulationResult sim = simulate(scenario, o.seed, 0);
  RunJobResult job;
  job.scenario_name = scenario.name;
  job.file = simulation_to_track_file(scenario, sim);
  TrackFile& file = job.file;
  {
    std::set<std::pair<int32_t, int32_t>> keys;
    for (std::size_t r = 0; r < file.tracks.size(); ++r)
      keys.insert({file.tracks.sensor[r], file.tracks.track[r]});
    job.local_tracks = keys.size();
  }
  if (on_scene) on_scene(job);

  auto chosen_by_name = [&](const std::string& name) {
    return o.solvers.empty() || contains(o.solvers, name);
  };
  auto add_row = [&](const AssociationOutcome& out) {  // scored, and stored as `associate` stores it
    const AssociationRecord& rec = out.record;
    const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
    file.metrics.push_back(to_metrics_record(rec.name, m));
    job.rows.push_back({rec.name, m, out.summary});
    store_outcome(file, out);
  };
  AssociatorOptions request;
  request.seed = o.seed;

  for (const auto& name : default_rows()) {
    if (!chosen_by_name(name)) continue;
    request.pipeline = o.pipeline;
    if (name == "default-chi2-gate") {
      request.pipeline.statistic.gate = GateMethod::kChiSquareSum;
      request.pipeline.alignment.method = AlignmentMethod::kForward;
      request.pipeline.alignment.process_noise = 1.0;
    }
    request.solver = name == "default-exact" ? "exact" : "lr+ls";
    request.solver_options = nlohmann::json::object();
    request.name = name;
    add_row(make_associator(AssociationPath::kSparseSD, request)->associate(file));
  }

  // The 3-D solvers on the three-sensor tensor (dense, or sparse with o.sparse), one problem for all.
  const bool three = file.sensors.size() == 3 || o.pipeline.sensors.size() == 3;
  bool any_3d = false;
  for (const auto& entry : solver_registry()) any_3d |= !o.solvers.empty() && chosen_by_name(entry.name);
  const bool due = any_3d || o.solvers.empty();
  job.three_d_skipped = !three && due;
  if (!three || !due) return job;
  PreparedThreeSensorProblem prepared;
  int32_t n = 0;  // the size that picks the default solvers (largest component when sparse)
  if (o.sparse) {
    SparsePipelineOptions sparse_options;
    sparse_options.pipeline = o.pipeline;
    auto sparse =
        std::make_shared<SparseAssociationProblem>(build_sparse_association_problem(file, sparse_options));
    for (int32_t c = 0; c < sparse->components.count; ++c) {
      const auto counts = component_track_counts(*sparse, c);
      n = std::max({n, counts[0], counts[1], counts[2]});
    }
    prepared.sparse = std::move(sparse);
  } else {
    require_dense_tensor_fits(file, o.pipeline);
    auto dense = std::make_shared<AssociationProblem>(build_association_problem(file, o.pipeline));
    n = std::max({dense->tensor.n1, dense->tensor.n2, dense->tensor.n3});
    prepared.dense = std::move(dense);
  }
  request.pipeline = o.pipeline;
  request.name.clear();
  for (const auto& entry : solver_registry()) {
    const bool chosen = o.solvers.empty() ? n <= entry.max_default_n : chosen_by_name(entry.name);
    if (!chosen) continue;
    request.solver = entry.name;
    request.solver_options =
        o.solver_options.contains(entry.name) ? o.solver_options[entry.name] : nlohmann::json::object();
    AssociationOutcome out = make_three_sensor_associator(request, prepared)->associate(file);
    // The record's time is the solve's; the problem was built once for every solver: its stages too.
    out.record.runtime_s += total_seconds(prepared.dense ? prepared.dense->stages : prepared.sparse->stages);
    out.summary.runtime_s = out.record.runtime_s;
    add_row(out);
  }
  return job;
}

std::string run_summary_path(const std::string& plot) { return report::sibling_picture(plot, "-summary"); }

void write_run_outputs(const RunJobResult& job, const std::string& output, const std::string& plot,
                       bool svg) {
  write_track_file(output, job.file);
  if (plot.empty() || job.rows.empty()) return;
  const report::ImageFormat format = report::picture_format(plot, svg);
  const std::string& first = job.rows.front().name;
  for (const AssociationRecord& rec : job.file.associations)
    if (rec.name == first)
      report::write_association_map(
          plot, format, job.file, rec,
          "trackassoc run, " + job.scenario_name + ": the '" + first + "' association");
  std::vector<report::SummaryRow> rows;
  for (const RunRow& r : job.rows)
    rows.push_back({r.name, r.metrics.correct_rate, r.metrics.false_rate, r.metrics.missed_rate,
                    r.summary.runtime_s, r.name == "default"});
  report::write_summary_chart(run_summary_path(plot), format,
                              "trackassoc run, " + job.scenario_name + ": every solver on the same recording",
                              rows);
}

}  // namespace trackassoc
