// trackassoc experiment NAME: the paper experiments and the studies of DESIGN §5. Each experiment
// registers itself as a sub-subcommand here (one line per experiment).
#include "engine/cli/common.hpp"

namespace trackassoc::cli {

void register_experiment(CLI::App& app) {
  auto* cmd = app.add_subcommand("experiment", "Reproduce a paper's study or run an engine study (DESIGN §5)");
  cmd->require_subcommand(1);
  register_experiment_scale(*cmd);
}

}  // namespace trackassoc::cli
