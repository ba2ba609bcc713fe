// trackassoc run: the main job. Simulates a scenario (default: the embedded seed 000 three-radar
// scenario), associates with every available solver, evaluates, prints a table and writes
// trackassoc-run.h5.
#include <array>
#include <iostream>
#include <optional>
#include <sstream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/metrics.hpp"
#include "engine/pipeline.hpp"
#include "engine/solver_registry.hpp"
#include "engine/sparse_pipeline.hpp"
#include "engine/workflow.hpp"

namespace trackassoc::cli {

void register_run(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    std::string scenario = "seed000", output = "trackassoc-run.h5";
    std::vector<std::string> solvers;
    HopfieldFlags hopfield;  // merged into the options of every Hopfield solver
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Simulate, associate with every solver, evaluate, print a table");
  cmd->add_option("--scenario", args->scenario, "Scenario JSON file or embedded name")->capture_default_str();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->capture_default_str();
  cmd->add_option("--solvers", args->solvers, "Solvers to run (default: all that suit the size)")
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
    for (const auto& s : args->solvers) find_solver(s);
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
    const Scenario scenario = load_scenario(args->scenario);
    const SimulationResult sim = simulate(scenario, args->common.seed, 0);
    TrackFile file = simulation_to_track_file(scenario, sim);
    // Dense (default) or sparse (--sparse) association problem, shared by all solvers.
    std::optional<AssociationProblem> dense;
    std::optional<SparseAssociationProblem> sparse;
    SparsePipelineOptions sparse_options;
    sparse_options.pipeline = options;
    std::array<int32_t, 3> n_tracks{}, ids{};
    std::size_t n_common = 0;
    int32_t n = 0;  // the size that picks the default solvers (largest component when sparse)
    if (args->pipeline.sparse) {
      sparse = build_sparse_association_problem(file, sparse_options);
      for (int d = 0; d < 3; ++d) n_tracks[d] = sparse->aligned[d].n_tracks();
      ids = sparse->sensor_ids;
      n_common = sparse->common_times.size();
      for (int32_t c = 0; c < sparse->components.count; ++c) {
        const auto counts = component_track_counts(*sparse, c);
        n = std::max({n, counts[0], counts[1], counts[2]});
      }
    } else {
      require_dense_tensor_fits(file, options);
      dense = build_association_problem(file, options);
      n_tracks = {dense->tensor.n1, dense->tensor.n2, dense->tensor.n3};
      ids = dense->sensor_ids;
      n_common = dense->common_times.size();
      n = std::max({n_tracks[0], n_tracks[1], n_tracks[2]});
    }

    std::cout << "scenario '" << scenario.name << "', seed " << args->common.seed << ": " << n_tracks[0]
              << " x " << n_tracks[1] << " x " << n_tracks[2] << " local tracks on sensors " << ids[0] << ", "
              << ids[1] << ", " << ids[2] << "; " << n_common << " common times; ";
    if (dense)
      std::cout << "statistics " << fmt(1e3 * dense->statistics_time_s, "%.2f") << " ms, cost tensor "
                << fmt(1e3 * dense->tensor_time_s, "%.2f") << " ms\n\n";
    else
      std::cout << "sparse: " << sparse->components.count << " components, largest " << n
                << " tracks per sensor\n\n";
    TextTable table({"solver", "objective", "lower bound", "gap", "correct", "false", "missed", "time [ms]",
                     "termination"});
    for (const auto& entry : solver_registry()) {
      const bool chosen = args->solvers.empty() ? n <= entry.max_default_n
                                                : std::find(args->solvers.begin(), args->solvers.end(),
                                                            entry.name) != args->solvers.end();
      if (!chosen) continue;
      const nlohmann::json entry_options =
          solver_options.contains(entry.name) ? solver_options[entry.name] : nlohmann::json::object();
      AssociationRecord rec =
          dense ? solve_association(*dense, entry.name, entry_options, args->common.seed, options)
                : solve_sparse_association(*sparse, entry.name, entry_options, args->common.seed,
                                           sparse_options);
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
