// trackassoc experiment NAME: the paper experiments (DESIGN §5). One line per experiment below;
// each add_experiment_<name> (engine/experiments.hpp) adds its own sub-subcommand.
#include "engine/cli/common.hpp"
#include "engine/experiments.hpp"

namespace trackassoc::cli {

void register_experiment(CLI::App& app) {
  auto* experiment = app.add_subcommand("experiment", "Reproduce a paper's study (HDF5, table, plots)");
  experiment->require_subcommand(1);
  add_experiment_seed002(experiment);
}

}  // namespace trackassoc::cli
