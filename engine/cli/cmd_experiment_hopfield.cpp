// trackassoc experiment schedules | seed000: the Hopfield experiments
// (engine/studies/seed000/experiment_schedules.hpp, engine/studies/seed000/experiment_seed000.hpp).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/seed000/experiment_schedules.hpp"
#include "engine/studies/seed000/experiment_seed000.hpp"

namespace trackassoc::cli {

void register_experiment_schedules(CLI::App& experiment) {
  auto args = std::make_shared<ExperimentArgs<SchedulesExperimentOptions>>();
  args->o.decomplib_dir = std::string(TRACKASSOC_DATA_DIR) + "/../../shared/benchmarks/3dap/decomplib";
  CLI::App* cmd = experiment.add_subcommand(
      "schedules",
      "Every Hopfield schedule and both energies vs greedy, greedy+LS and LR (seed000 tracking, DecompLib)");
  cmd->add_option("--sizes", args->o.tracking_sizes, "Tracking instance sizes (targets)")
      ->capture_default_str()
      ->check(in_range(1, 200));
  cmd->add_option("--runs", args->o.runs, "Tracking instances per size")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--decomplib-sizes", args->o.decomplib_sizes, "DecompLib sizes (10, 20, 30, 40)")
      ->capture_default_str()
      ->check(in_range(10, 40));
  cmd->add_option("--decomplib-per-size", args->o.decomplib_per_size, "DecompLib instances per size (0..10)")
      ->capture_default_str()
      ->check(in_range(0, 10));
  cmd->add_option("--decomplib-dir", args->o.decomplib_dir, "Folder of ap3.*.txt and ap3.opt")
      ->capture_default_str();
  cmd->add_option("--restarts", args->o.restarts, "Restarts of every network")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--methods", args->o.methods, "Only these methods (table names; default: all)");
  finish_experiment_command(
      cmd, args, "SVG plot of gap vs wall time ('' = none)",
      [](const SchedulesExperimentOptions& o, std::ostream* progress) {
        const auto rows = run_schedules_experiment(o, progress);
        if (!distributed::world().root()) return;  // rank 0 has the rows
        std::cout << schedules_summary_table(rows);
        write_schedules_outputs(rows, o);
      },
      /*sharded=*/true);
}

void register_experiment_seed000(CLI::App& experiment) {
  auto args = std::make_shared<ExperimentArgs<Seed000ExperimentOptions>>();
  CLI::App* cmd = experiment.add_subcommand(
      "seed000", "Seed 000 Monte Carlo: correct association of hopfield-paper, hopfield, chnn, lr and exact");
  cmd->add_option("--targets", args->o.targets, "Target counts")
      ->capture_default_str()
      ->check(in_range(1, 200));
  cmd->add_option("--runs", args->o.runs, "Monte Carlo runs per configuration")
      ->capture_default_str()
      ->check(in_range(1, 100000));
  cmd->add_option("--process-noise", args->o.process_noise,
                  "σ_a [m/s²] of the targets' white-noise acceleration in the correlated-error case (errors "
                  "correlated through common process noise, Bar-Shalom–Campo)")
      ->capture_default_str()
      ->check(in_range(0, 100, true, false));
  cmd->add_option("--forms", args->o.forms, "Cost forms: chain (Eq. 3, separable) and/or all-pairs")
      ->capture_default_str()
      ->check(enum_choices<CostForm>());
  cmd->add_option("--solvers", args->o.solvers, "Solvers to compare")->capture_default_str();
  finish_experiment_command(
      cmd, args, "SVG plot ('' = none)",
      [](const Seed000ExperimentOptions& o, std::ostream* progress) {
        const auto rows = run_seed000_experiment(o, progress);
        if (!distributed::world().root()) return;  // rank 0 has the rows
        std::cout << seed000_summary_table(rows, o);
        write_seed000_outputs(rows, o);
      },
      /*sharded=*/true);
}

}  // namespace trackassoc::cli
