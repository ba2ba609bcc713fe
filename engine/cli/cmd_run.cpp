// trackassoc run: the main job. Simulates a scenario (default: `recorded_formation`, a realistic
// recording of the family of engine/experiment_recorded.hpp: asynchronous radars, partial and false
// tracks, turns, and targets flying in groups of three 400 m apart, where the gates and the solvers
// differ), associates with the default pipeline (every sensor, sparse S-D, calibrated gate), the same
// with the exact solver and with seed 000's gate, and every 3-D solver that suits the size,
// evaluates, prints a table (correct, false, missed, false tuples, time), and writes
// trackassoc-run.h5 and a plot of correct association against time (trackassoc-run.svg).
#include <array>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/experiment_schedules.hpp"
#include "engine/metrics.hpp"
#include "engine/pipeline.hpp"
#include "engine/solver_registry.hpp"
#include "engine/sparse_pipeline.hpp"
#include "engine/sparse_sd_pipeline.hpp"
#include "engine/workflow.hpp"
#include "io/atomic_file.hpp"

namespace trackassoc::cli {
namespace {

// run's --options is keyed by solver name. A key that names no solver (a misspelling), or a solver
// that --solvers leaves out, would be ignored silently: both are input errors, and so is a key of a
// solver's own options that the solver does not read, found here by solving the 1×1×1 instance
// with them (every solver parses its options before it looks at the tensor) before any work.
void check_run_solver_options(const nlohmann::json& options, const std::vector<std::string>& solvers) {
  std::vector<std::string> names;
  for (const auto& e : solver_registry()) names.push_back(e.name);
  for (auto it = options.begin(); it != options.end(); ++it) {
    const std::string& name = it.key();
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw InputError(
          "--options: " + unknown_name_message("solver", name, names) +
          " (run's --options is keyed by solver name, e.g. '{\"hopfield\": {\"restarts\": 8}}')");
    if (!it.value().is_object())
      throw InputError("--options: '" + name + "': expected a JSON object of that solver's options, found " +
                       it.value().dump());
    if (!solvers.empty() && std::find(solvers.begin(), solvers.end(), name) == solvers.end())
      throw InputError("--options: '" + name + "' has options but is not in --solvers");
    find_solver(name).solve(CostTensor3(1, 1, 1), it.value(), 1);
  }
}

}  // namespace

void register_run(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    std::string scenario = "recorded_formation", output = "trackassoc-run.h5", plot = "trackassoc-run.svg";
    std::vector<std::string> solvers;
    HopfieldFlags hopfield;  // merged into the options of every Hopfield solver
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Simulate, associate with every solver, evaluate, print a table");
  cmd->add_option("--scenario", args->scenario, "Scenario JSON file or embedded name")->capture_default_str();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->capture_default_str();
  cmd->add_option("--plot", args->plot, "SVG plot of correct association vs time ('' = none)")
      ->capture_default_str();
  cmd->add_option("--solvers", args->solvers,
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
    const PipelineOptions options = resolve(args->pipeline);
    nlohmann::json solver_options = parse_solver_options(args->pipeline.solver_options);
    const std::vector<std::string> pipeline_rows{"default", "default-exact", "default-chi2-gate"};
    auto chosen_by_name = [&](const std::string& name) {
      return args->solvers.empty() ||
             std::find(args->solvers.begin(), args->solvers.end(), name) != args->solvers.end();
    };
    for (const auto& s : args->solvers)
      if (std::find(pipeline_rows.begin(), pipeline_rows.end(), s) == pipeline_rows.end()) find_solver(s);
    check_run_solver_options(solver_options, args->solvers);
    if (args->hopfield.any()) {  // the flags go to every Hopfield solver of the run
      bool any_hopfield = args->solvers.empty();
      for (const auto& s : args->solvers) any_hopfield |= is_hopfield_solver(s);
      if (!any_hopfield)
        throw InputError(
            "--schedule/--restarts/--polish/--trace: --solvers names no Hopfield solver "
            "(hopfield, hopfield-paper, chnn)");
      // Without --solvers (every solver runs), --schedule goes to the Hopfield solvers whose network
      // has that schedule and the others keep theirs (diagonal: hopfield only); a solver named in
      // --solvers that cannot take it is an error, and so is a schedule that none can take.
      std::vector<std::string> skipped;
      std::string rejection;
      for (const char* s : kHopfieldSolvers) {
        HopfieldFlags flags = args->hopfield;
        if (!flags.schedule.empty() && args->solvers.empty()) {
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
      if (skipped.size() == kHopfieldSolvers.size())
        throw InputError("--schedule " + args->hopfield.schedule + ": " + rejection);
      if (!skipped.empty()) {
        std::string list;
        for (const auto& s : skipped) list += (list.empty() ? "" : ", ") + s;
        std::cerr << "note: --schedule " << args->hopfield.schedule << " is not a schedule of " << list
                  << ", which keep their own\n";
      }
    }
    check_output_paths({{args->output, "--output"}, {args->plot, "--plot"}});  // before any work
    const Scenario scenario = load_scenario(args->scenario);
    const SimulationResult sim = simulate(scenario, args->common.seed, 0);
    TrackFile file = simulation_to_track_file(scenario, sim);
    TextTable table({"solver", "correct", "false", "missed", "false tuples", "time [ms]", "objective",
                     "lower bound", "gap", "termination"});
    std::vector<SvgSeries> series;
    auto add_row = [&](AssociationRecord rec) {
      const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
      file.metrics.push_back(to_metrics_record(rec.name, m));
      table.add({rec.name, percent(m.correct_rate), percent(m.false_rate), percent(m.missed_rate),
                 std::to_string(m.false_tuples) + " of " + std::to_string(m.linked_tuples),
                 fmt(1e3 * rec.runtime_s, "%.3f"), fmt(rec.objective, "%.6g"), fmt(rec.lower_bound, "%.6g"),
                 percent(rec.gap), rec.termination});
      series.push_back({rec.name, {std::max(1e-3, 1e3 * rec.runtime_s)}, {100.0 * m.correct_rate}});
      file.associations.push_back(std::move(rec));
    };
    std::size_t file_tracks = 0;
    {
      std::set<std::pair<int32_t, int32_t>> keys;
      for (std::size_t r = 0; r < file.tracks.size(); ++r)
        keys.insert({file.tracks.sensor[r], file.tracks.track[r]});
      file_tracks = keys.size();
    }
    std::cout << "scenario '" << scenario.name << "', seed " << args->common.seed << ": "
              << file.sensors.size() << " sensors, " << file_tracks << " local tracks\n\n";

    // The default pipeline (what `associate` does without flags), its exact solver, and seed 000's
    // gate in the same pipeline.
    for (const auto& name : pipeline_rows) {
      if (!chosen_by_name(name)) continue;
      SparseSDOptions so;
      so.pipeline = options;
      if (name == "default-chi2-gate") {
        so.pipeline.statistic.gate = GateMethod::kChiSquareSum;
        so.pipeline.alignment.method = AlignmentMethod::kForward;
        so.pipeline.alignment.process_noise = 1.0;
      }
      const std::string solver = name == "default-exact" ? "exact" : "lr+ls";
      AssociationRecord rec =
          associate_sparse_sd(file, solver, nlohmann::json::object(), args->common.seed, so);
      rec.name = name;
      add_row(std::move(rec));
    }

    // The 3-D solvers on the three-sensor tensor (dense, or sparse with --sparse).
    const bool three = file.sensors.size() == 3 || options.sensors.size() == 3;
    bool any_3d = false;
    for (const auto& entry : solver_registry())
      any_3d |= !args->solvers.empty() && chosen_by_name(entry.name);
    if (!three && (any_3d || args->solvers.empty()))
      std::cout << "note: the 3-D solvers take three sensors (--sensors A,B,C); the file has "
                << file.sensors.size() << ", so only the default pipeline ran\n";
    std::optional<AssociationProblem> dense;
    std::optional<SparseAssociationProblem> sparse;
    SparsePipelineOptions sparse_options;
    sparse_options.pipeline = options;
    int32_t n = 0;  // the size that picks the default solvers (largest component when sparse)
    if (three && (any_3d || args->solvers.empty())) {
      if (args->pipeline.sparse) {
        sparse = build_sparse_association_problem(file, sparse_options);
        for (int32_t c = 0; c < sparse->components.count; ++c) {
          const auto counts = component_track_counts(*sparse, c);
          n = std::max({n, counts[0], counts[1], counts[2]});
        }
      } else {
        require_dense_tensor_fits(file, options);
        dense = build_association_problem(file, options);
        n = std::max({dense->tensor.n1, dense->tensor.n2, dense->tensor.n3});
      }
      for (const auto& entry : solver_registry()) {
        const bool chosen = args->solvers.empty() ? n <= entry.max_default_n : chosen_by_name(entry.name);
        if (!chosen) continue;
        const nlohmann::json entry_options =
            solver_options.contains(entry.name) ? solver_options[entry.name] : nlohmann::json::object();
        AssociationRecord rec =
            dense ? solve_association(*dense, entry.name, entry_options, args->common.seed, options)
                  : solve_sparse_association(*sparse, entry.name, entry_options, args->common.seed,
                                             sparse_options);
        if (dense) rec.runtime_s += dense->statistics_time_s + dense->tensor_time_s;
        add_row(std::move(rec));
      }
    }
    table.print(std::cout);
    std::cout
        << "\ncorrect / false / missed: of the targets tracked by >= 2 sensors (trackassoc evaluate's rule); "
           "time: statistics + cost + solve; default*: the default pipeline (every sensor, sparse S-D); the "
           "other rows: the 3-D solvers on the three-sensor tensor (seed 000 Eq. 3, all-pairs)\n";
    write_track_file(args->output, file);
    if (!args->plot.empty()) {
      const std::string svg =
          svg_scatter("trackassoc run, " + scenario.name + ": correct association vs time",
                      "association time [ms]", "correct association [%]", series, true);
      write_atomically(args->plot, [&](const std::string& tmp) { std::ofstream(tmp) << svg; });
    }
    std::cout << "\nwrote " << args->output << (args->plot.empty() ? "" : " and " + args->plot) << "\n";
  });
}

}  // namespace trackassoc::cli
