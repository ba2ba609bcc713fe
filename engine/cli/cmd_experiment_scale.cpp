// trackassoc experiment scale (issue 6): the sparse path from 10² to 10⁴ targets per sensor.
// Prints the table (time per stage, peak memory, correct rate, dense beside it where it fits),
// writes DIR/scale.h5 (the result, layout in engine/studies/scale/experiment_scale.hpp) and, for a quick
// look, DIR/scale.csv and DIR/scale.json, all atomically (write_scale_outputs), and draws DIR/scale.png (or
// --plots PNG) from the HDF5 file with scripts/plot_scale.py (run_plot_script).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "engine/cli/association_flags.hpp"
#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/scale/experiment_scale.hpp"

namespace trackassoc::cli {

void register_experiment_scale(CLI::App& experiment) {
  struct Args {
    CommonOptions common;
    ScaleExperimentOptions options;
    std::string solver_options = "{}";
    std::string output = "results/scale", plots;  // plots "": OUTPUT/scale.png
    bool no_isolate = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = experiment.add_subcommand(
      "scale",
      "Sparse association from 10^2 to 10^4 targets per sensor: time and peak memory per stage, "
      "correct rate, dense path beside it where it fits");
  auto& o = args->options;
  cmd->add_option("--sizes", o.sizes, "Targets per sensor, comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--dense-max", o.dense_max, "Run the dense path too up to this size")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--solver", o.solver, "Solver for every component (and the dense path)")
      ->capture_default_str();
  cmd->add_option("--options", args->solver_options, "Solver options as a JSON object")
      ->capture_default_str();
  cmd->add_option("--density", o.density, "Targets per 100 km^2 of ground")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--gate", o.gate_probability, "Chi-square gate probability")
      ->capture_default_str()
      ->check(in_range(0, 1, true, true));
  cmd->add_option("--duration", o.tracks.duration, "Track set duration [s]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--sigma-pos", o.tracks.sigma_pos, "Local track position error sigma [m]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--p-seen", o.tracks.p_seen, "Probability that a sensor holds a track of a target")
      ->capture_default_str()
      ->check(in_range(0, 1));
  cmd->add_option("--min-lifetime", o.tracks.min_lifetime_fraction,
                  "Each local track covers a random part of the duration, at least this fraction (1 = all)")
      ->capture_default_str()
      ->check(in_range(0, 1, true));
  cmd->add_flag_function(
      "--two-d", [args](int64_t) { args->options.tracks.three_d = false; }, "2-D targets (default 3-D)");
  cmd->add_flag("--no-isolate", args->no_isolate,
                "Run every size in this process (peak memory is then cumulative)");
  finish_study_command(
      cmd, args,
      {.output = &args->output,
       .output_help = "Output folder",
       .output_is_folder = true,
       .plots = &args->plots,
       .plots_help = "PNG plot (scripts/plot_scale.py; default OUTPUT/scale.png)"},
      [args](std::ostream*, bool plots) {
        ScaleExperimentOptions o = args->options;
        o.seed = args->common.seed;
        o.threads = args->common.threads;
        o.isolate = !args->no_isolate;
        o.solver_options = parse_solver_options(args->solver_options);
        o.validate();
        find_solver(o.solver);
        std::filesystem::create_directories(args->output);
        const bool tty = isatty(STDERR_FILENO);
        auto rows = run_scale_experiment(o, [&](const ScaleRow& r) {
          if (tty) std::cerr << "scale: n = " << r.n << " done in " << r.total_s << " s\n";
        });
        std::cout << "experiment scale: 3 sensors, solver '" << o.solver << "', density " << o.density
                  << " targets / 100 km^2, gate " << o.gate_probability << ", threads "
                  << (o.threads ? std::to_string(o.threads) : std::string("all")) << "\n\n"
                  << scale_table(rows);
        const double slope = scaling_exponent(rows, 1000);
        std::printf(
            "\nlog-log slope of total time vs n for n >= 1000: %.2f (n log n gives about 1.1 here, n^2 gives "
            "2)\n",
            slope);
        write_scale_outputs(args->output, rows, o, slope);
        const std::string dir = args->output, h5 = dir + "/scale.h5";
        std::cout << "wrote " << h5 << ", " << dir << "/scale.csv, " << dir << "/scale.json\n";
        const std::string png = args->plots.empty() ? dir + "/scale.png" : args->plots;
        if (plots && run_plot_script("plot_scale.py", {h5, png})) std::cout << "wrote " << png << "\n";
      });
}

}  // namespace trackassoc::cli
