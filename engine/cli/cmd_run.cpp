// trackassoc run: the main job (engine/jobs/run_job.hpp). Simulates a scenario (default:
// `recorded_formation`), associates with the default pipeline, the same with the exact solver and
// with seed 000's gate, and every 3-D solver that suits the size, evaluates, prints a table
// (correct, false, missed, false tuples, time), and writes trackassoc-run.h5, the recording as a
// map with the default association (trackassoc-run.png) and a summary chart of every solver
// (trackassoc-run-summary.png); --svg for SVG. This command parses the flags, merges
// the Hopfield flags into the Hopfield solvers' options, calls the job and prints.
#include <iostream>

#include "engine/cli/association_flags.hpp"
#include "engine/cli/common.hpp"
#include "engine/cli/hopfield_flags.hpp"
#include "engine/cli/table.hpp"
#include "engine/jobs/run_job.hpp"
#include "engine/report/figure.hpp"

namespace trackassoc::cli {
namespace {

// --schedule/--restarts/--polish/--trace go to every Hopfield solver of the run. Without --solvers
// (every solver runs), --schedule goes to the Hopfield solvers whose network has that schedule and
// the others keep theirs (diagonal: hopfield only); a solver named in --solvers that cannot take
// it is an error, and so is a schedule that none can take.
void merge_run_hopfield_flags(const HopfieldFlags& hopfield, const std::vector<std::string>& solvers,
                              nlohmann::json& solver_options) {
  if (!hopfield.any()) return;
  bool any_hopfield = solvers.empty();
  for (const auto& s : solvers) any_hopfield |= is_hopfield_solver(s);
  if (!any_hopfield)
    throw InputError("--schedule/--restarts/--polish/--trace: --solvers names no Hopfield solver (" +
                     list_names(hopfield_solver_names(), ", ") + ")");
  std::vector<std::string> skipped;
  std::string rejection;
  const std::vector<std::string> hopfield_solvers = hopfield_solver_names();
  for (const std::string& s : hopfield_solvers) {
    HopfieldFlags flags = hopfield;
    if (!flags.schedule.empty() && solvers.empty()) {
      const std::string why = hopfield_schedule_rejection(s, flags.schedule);
      if (!why.empty()) {
        skipped.push_back(s);
        if (rejection.empty()) rejection = why;
        flags.schedule.clear();
      }
    }
    nlohmann::json o = solver_options.contains(s) ? solver_options[s] : nlohmann::json::object();
    merge_hopfield_flags(flags, s, o);
    solver_options[s] = o;
  }
  if (skipped.size() == hopfield_solvers.size())
    throw InputError("--schedule " + hopfield.schedule + ": " + rejection);
  if (!skipped.empty()) {
    std::string list;
    for (const auto& s : skipped) list += (list.empty() ? "" : ", ") + s;
    std::cerr << "note: --schedule " << hopfield.schedule << " is not a schedule of " << list
              << ", which keep their own\n";
  }
}

}  // namespace

void register_run(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    RunJobOptions job;
    std::string output = "trackassoc-run.h5", plot = "trackassoc-run.png";
    HopfieldFlags hopfield;  // merged into the options of every Hopfield solver
    bool no_plots = false, svg = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Simulate, associate with every solver, evaluate, print a table");
  cmd->add_option("--scenario", args->job.scenario, "Scenario JSON file or embedded name")
      ->capture_default_str();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->capture_default_str();
  cmd->add_option("--plots", args->plot,
                  "The map of the default association (PNG); the summary chart of every solver goes "
                  "beside it as NAME-summary.png")
      ->capture_default_str();
  cmd->add_flag("--svg", args->svg, "Draw the pictures as SVG (the --plots name's .png becomes .svg)");
  cmd->add_flag("--no-plots", args->no_plots, "Draw no plot");
  cmd->add_option("--solvers", args->job.solvers,
                  "Solvers to run (default: all that suit the size): default, default-exact, "
                  "default-chi2-gate (the default pipeline), or 3-D solver names")
      ->delimiter(',');
  add_pipeline_options(cmd, args->pipeline);
  add_hopfield_flags(cmd, args->hopfield, true);
  cmd->get_option("--options")
      ->description(
          "Per-solver options as JSON keyed by solver name, e.g. '{\"hopfield\": {\"restarts\": 8}}'");
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    if (args->no_plots) args->plot.clear();
    args->plot = report::picture_path(args->plot, args->svg);
    const std::string summary = args->plot.empty() ? "" : run_summary_path(args->plot);
    RunJobOptions& job = args->job;
    job.pipeline = resolve(args->pipeline);
    job.solver_options = parse_solver_options(args->pipeline.solver_options);
    job.sparse = args->pipeline.sparse;
    job.seed = args->common.seed;
    check_run_solver_options(job.solver_options, job.solvers);
    merge_run_hopfield_flags(args->hopfield, job.solvers, job.solver_options);
    check_output_paths(
        {{args->output, "--output"}, {args->plot, "--plots"}, {summary, "--plots"}},  // before any work
        {{job.scenario, "--scenario"}});
    const RunJobResult result = run_main_job(job, [&](const RunJobResult& scene) {
      std::cout << "scenario '" << scene.scenario_name << "', seed " << job.seed << ": "
                << scene.file.sensors.size() << " sensors, " << scene.local_tracks << " local tracks\n\n";
    });
    if (result.three_d_skipped)
      std::cout << "note: the 3-D solvers take three sensors (--sensors A,B,C); the file has "
                << result.file.sensors.size() << ", so only the default pipeline ran\n";
    TextTable table({"solver", "correct", "false", "missed", "false tuples", "time [ms]", "objective",
                     "lower bound", "gap", "termination"});
    for (const RunRow& r : result.rows)
      table.add({r.name, percent(r.metrics.correct_rate), percent(r.metrics.false_rate),
                 percent(r.metrics.missed_rate),
                 std::to_string(r.metrics.false_tuples) + " of " + std::to_string(r.metrics.linked_tuples),
                 fmt(1e3 * r.summary.runtime_s, "%.3f"), fmt(r.summary.objective, "%.6g"),
                 fmt(r.summary.lower_bound, "%.6g"), percent(r.summary.gap), r.summary.termination});
    table.print(std::cout);
    std::cout
        << "\ncorrect / false / missed: of the targets tracked by >= 2 sensors (trackassoc evaluate's rule); "
           "time: statistics + cost + solve; default*: the default pipeline (every sensor, sparse S-D); the "
           "other rows: the 3-D solvers on the three-sensor tensor (seed 000 Eq. 3, all-pairs)\n";
    write_run_outputs(result, args->output, args->plot, args->svg);
    std::cout << "\nwrote " << args->output
              << (args->plot.empty() ? "" : ", " + args->plot + " and " + summary) << "\n";
  });
}

}  // namespace trackassoc::cli
