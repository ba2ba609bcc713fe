// trackassoc experiment schedules | seed000: the Hopfield experiments (engine/experiment_schedules.hpp,
// engine/experiment_seed000.hpp).
#include <unistd.h>

#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/experiment_schedules.hpp"
#include "engine/experiment_seed000.hpp"

namespace trackassoc::cli {

namespace {
std::ostream* progress_stream() { return isatty(STDERR_FILENO) ? &std::cerr : nullptr; }
}  // namespace

void register_experiment_schedules(CLI::App& experiment) {
  struct Args {
    SchedulesExperimentOptions o;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  args->o.decomplib_dir = std::string(TRACKASSOC_DATA_DIR) + "/../../shared/benchmarks/3dap/decomplib";
  CLI::App* cmd = experiment.add_subcommand(
      "schedules",
      "Every Hopfield schedule and both energies vs greedy, greedy+LS and LR (seed000 tracking, DecompLib)");
  cmd->add_option("--sizes", args->o.tracking_sizes, "Tracking instance sizes (targets)")
      ->capture_default_str();
  cmd->add_option("--runs", args->o.runs, "Tracking instances per size")->capture_default_str();
  cmd->add_option("--decomplib-sizes", args->o.decomplib_sizes, "DecompLib sizes (10, 20, 30, 40)")
      ->capture_default_str();
  cmd->add_option("--decomplib-per-size", args->o.decomplib_per_size, "DecompLib instances per size (0..10)")
      ->capture_default_str();
  cmd->add_option("--decomplib-dir", args->o.decomplib_dir, "Folder of ap3.*.txt and ap3.opt")
      ->capture_default_str();
  cmd->add_option("--restarts", args->o.restarts, "Restarts of every network")->capture_default_str();
  cmd->add_option("--methods", args->o.methods, "Only these methods (table names; default: all)");
  cmd->add_option("--output", args->o.output, "HDF5 output")->capture_default_str();
  cmd->add_option("--plot", args->o.plot, "SVG plot of gap vs wall time ('' = none)")->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    args->o.seed = args->common.seed;
    const auto rows = run_schedules_experiment(args->o, progress_stream());
    std::cout << schedules_summary_table(rows);
    write_schedules_outputs(rows, args->o);
    std::cout << "\nwrote " << args->o.output << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
  });
}

void register_experiment_seed000(CLI::App& experiment) {
  struct Args {
    Seed000ExperimentOptions o;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = experiment.add_subcommand(
      "seed000", "Seed 000 Monte Carlo: correct association of hopfield-paper, hopfield, chnn, lr and exact");
  cmd->add_option("--targets", args->o.targets, "Target counts")->capture_default_str();
  cmd->add_option("--runs", args->o.runs, "Monte Carlo runs per configuration")->capture_default_str();
  cmd->add_option("--correlation", args->o.correlation, "ρ of the correlated-error case")
      ->capture_default_str();
  cmd->add_option("--solvers", args->o.solvers, "Solvers to compare")->capture_default_str();
  cmd->add_option("--output", args->o.output, "HDF5 output")->capture_default_str();
  cmd->add_option("--plot", args->o.plot, "SVG plot ('' = none)")->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    args->o.seed = args->common.seed;
    const auto rows = run_seed000_experiment(args->o, progress_stream());
    std::cout << seed000_summary_table(rows, args->o);
    write_seed000_outputs(rows, args->o);
    std::cout << "\nwrote " << args->o.output << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
  });
}

}  // namespace trackassoc::cli
