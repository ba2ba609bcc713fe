// trackassoc experiment NAME: the paper experiments and the engine studies (docs/design.md §5). Each
// experiment is a sub-subcommand registered by one line below; it writes its results (HDF5 or
// CSV/JSON), prints a table beside the paper's numbers and saves a plot.
#include "engine/cli/common.hpp"
#include "engine/studies/experiments.hpp"

namespace trackassoc::cli {

void register_experiment(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("experiment",
                                     "Reproduce a paper's study or run an engine study (docs/design.md §5)");
  cmd->require_subcommand(1);
  register_experiment_seed000(*cmd);
  register_experiment_seed001(*cmd);
  register_experiment_seed002(*cmd);
  register_experiment_seed003(*cmd);
  register_experiment_seed004(*cmd);
  register_experiment_schedules(*cmd);
  register_experiment_scale(*cmd);
  register_experiment_recorded(*cmd);
}

}  // namespace trackassoc::cli
