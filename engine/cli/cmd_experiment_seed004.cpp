// trackassoc experiment seed004: the improved CHNN with pseudo-tracks on four asynchronous 3-D
// sensors (engine/experiment_seed004.hpp).
#include <unistd.h>

#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/experiment_seed004.hpp"

namespace trackassoc::cli {

void register_experiment_seed004(CLI::App& experiment) {
  struct Args {
    Seed004ExperimentOptions o;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = experiment.add_subcommand(
      "seed004",
      "Seed 004: CHNN with pseudo-tracks (Eq. 12 vs Eq. 7), S-D LR and exact on 4 sensors, 5 and 25 targets");
  cmd->add_option("--scenarios", args->o.scenarios, "Scenarios (embedded names or JSON files)")
      ->capture_default_str();
  cmd->add_option("--runs", args->o.runs, "Monte Carlo runs per scenario")->capture_default_str();
  cmd->add_option("--p-miss", args->o.p_miss,
                  "Chance that a sensor has no track of a target (unequal counts)")
      ->capture_default_str();
  cmd->add_option("--solvers", args->o.solvers, "chnn-eq12-single, chnn-eq12, chnn-eq7, lr, lr+ls, exact")
      ->capture_default_str();
  cmd->add_option("--exact-time-limit", args->o.exact_time_limit_s,
                  "Time limit of the exact search per run [s]")
      ->capture_default_str();
  cmd->add_option("--output", args->o.output, "HDF5 output")->capture_default_str();
  cmd->add_option("--plot", args->o.plot, "SVG plot ('' = none)")->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    args->o.seed = args->common.seed;
    const auto rows = run_seed004_experiment(args->o, isatty(STDERR_FILENO) ? &std::cerr : nullptr);
    std::cout << seed004_summary_table(rows, args->o);
    write_seed004_outputs(rows, args->o);
    std::cout << "\nwrote " << args->o.output << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
  });
}

}  // namespace trackassoc::cli
