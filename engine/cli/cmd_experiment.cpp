// trackassoc experiment NAME: reproduces a paper's study (DESIGN §5). Each experiment registers
// itself as a sub-subcommand; add one line below per experiment.
#include "engine/cli/common.hpp"

namespace trackassoc::cli {

void register_experiment(CLI::App& app) {
  auto* cmd = app.add_subcommand("experiment", "Reproduce a paper's study: prints a table beside the paper's figures, "
                                               "writes an HDF5 file and plots");
  cmd->require_subcommand(1);
  register_experiment_seed001(*cmd);
}

}  // namespace trackassoc::cli
