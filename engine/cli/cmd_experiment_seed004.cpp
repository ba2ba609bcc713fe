// trackassoc experiment seed004: the improved CHNN with pseudo-tracks on four asynchronous 3-D
// sensors (engine/studies/seed004/experiment_seed004.hpp).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/seed004/experiment_seed004.hpp"

namespace trackassoc::cli {

void register_experiment_seed004(CLI::App& experiment) {
  auto args = std::make_shared<ExperimentArgs<Seed004ExperimentOptions>>();
  CLI::App* cmd = experiment.add_subcommand(
      "seed004",
      "Seed 004: CHNN with pseudo-tracks (Eq. 12 vs Eq. 7), S-D LR and exact on 4 sensors, 5 and 25 targets");
  cmd->add_option("--scenarios", args->o.scenarios, "Scenarios (embedded names or JSON files)")
      ->capture_default_str();
  cmd->add_option("--runs", args->o.runs, "Monte Carlo runs per scenario")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--p-miss", args->o.p_miss,
                  "Chance that a sensor has no track of a target (unequal counts)")
      ->capture_default_str()
      ->check(in_range(0, 1, false, true));
  cmd->add_option("--solvers", args->o.solvers, "chnn-eq12-single, chnn-eq12, chnn-eq7, lr, lr+ls, exact")
      ->capture_default_str();
  cmd->add_option("--exact-time-limit", args->o.exact_time_limit_s,
                  "Time limit of the exact search per run [s]")
      ->capture_default_str()
      ->check(above(0));
  finish_experiment_command(
      cmd, args, "SVG plot ('' = none)",
      [](const Seed004ExperimentOptions& o, std::ostream* progress) {
        const auto rows = run_seed004_experiment(o, progress);
        if (!distributed::world().root()) return;  // rank 0 has the rows
        std::cout << seed004_summary_table(rows, o);
        write_seed004_outputs(rows, o);
      },
      /*sharded=*/true);
}

}  // namespace trackassoc::cli
