// trackassoc run: the main job. Simulates a scenario (default: the embedded seed 000 three-radar
// scenario), associates with every available solver, evaluates, prints a table and writes
// trackassoc-run.h5.
#include <iostream>
#include <sstream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/metrics.hpp"
#include "engine/pipeline.hpp"
#include "engine/solver_registry.hpp"
#include "engine/workflow.hpp"

namespace trackassoc::cli {

void register_run(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    std::string scenario = "seed000", output = "trackassoc-run.h5";
    std::vector<std::string> solvers;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Simulate, associate with every solver, evaluate, print a table");
  cmd->add_option("--scenario", args->scenario, "Scenario JSON file or embedded name")->capture_default_str();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->capture_default_str();
  cmd->add_option("--solvers", args->solvers, "Solvers to run (default: all that suit the size)")
      ->delimiter(',');
  add_pipeline_options(cmd, args->pipeline);
  cmd->get_option("--options")
      ->description(
          "Per-solver options as JSON keyed by solver name, e.g. '{\"hopfield\": {\"restarts\": 8}}'");
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    const PipelineOptions options = resolve(args->pipeline);
    const nlohmann::json solver_options = parse_solver_options(args->pipeline.solver_options);
    for (const auto& s : args->solvers) find_solver(s);
    const Scenario scenario = load_scenario(args->scenario);
    const SimulationResult sim = simulate(scenario, args->common.seed, 0);
    TrackFile file = simulation_to_track_file(scenario, sim);
    const AssociationProblem problem = build_association_problem(file, options);
    const int32_t n = std::max({problem.tensor.n1, problem.tensor.n2, problem.tensor.n3});

    std::cout << "scenario '" << scenario.name << "', seed " << args->common.seed << ": " << problem.tensor.n1
              << " x " << problem.tensor.n2 << " x " << problem.tensor.n3 << " local tracks on sensors "
              << problem.sensor_ids[0] << ", " << problem.sensor_ids[1] << ", " << problem.sensor_ids[2]
              << "; " << problem.common_times.size() << " common times; statistics "
              << fmt(1e3 * problem.statistics_time_s, "%.2f") << " ms, cost tensor "
              << fmt(1e3 * problem.tensor_time_s, "%.2f") << " ms\n\n";
    TextTable table({"solver", "objective", "lower bound", "gap", "correct", "false", "missed", "time [ms]",
                     "termination"});
    for (const auto& entry : solver_registry()) {
      const bool chosen = args->solvers.empty() ? n <= entry.max_default_n
                                                : std::find(args->solvers.begin(), args->solvers.end(),
                                                            entry.name) != args->solvers.end();
      if (!chosen) continue;
      AssociationRecord rec = solve_association(
          problem, entry.name,
          solver_options.contains(entry.name) ? solver_options[entry.name] : nlohmann::json::object(),
          args->common.seed, options);
      const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
      file.metrics.push_back(to_metrics_record(rec.name, m));
      table.add({rec.name, fmt(rec.objective, "%.6g"), fmt(rec.lower_bound, "%.6g"), percent(rec.gap),
                 percent(m.correct_rate), percent(m.false_rate), percent(m.missed_rate),
                 fmt(1e3 * rec.runtime_s, "%.3f"), rec.termination});
      file.associations.push_back(std::move(rec));
    }
    table.print(std::cout);
    write_track_file(args->output, file);
    std::cout << "\nwrote " << args->output << "\n";
  });
}

}  // namespace trackassoc::cli
