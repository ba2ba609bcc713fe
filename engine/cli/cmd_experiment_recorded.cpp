// trackassoc experiment recorded: the default association on the realistic-recording family, with
// Stone Soup on the same files (engine/studies/recorded/experiment_recorded.hpp).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/recorded/experiment_recorded.hpp"

namespace trackassoc::cli {

void register_experiment_recorded(CLI::App& experiment) {
  auto args = std::make_shared<ExperimentArgs<RecordedExperimentOptions>>();
  args->o.peer_script = TRACKASSOC_DATA_DIR "/../bench/stonesoup_t2t.py";
  CLI::App* cmd = experiment.add_subcommand(
      "recorded",
      "The default association on the realistic-recording family (asynchronous sensors, partial and false "
      "tracks, turns, dense and formation cases, 3-5 sensors), beside Stone Soup on the same files");
  cmd->add_option("--scenarios", args->o.scenarios, "Scenarios (embedded names or JSON files)")
      ->capture_default_str();
  cmd->add_option("--methods", args->o.methods, "default, exact, chi2-sum, 3d-exact, 3d-nogate")
      ->capture_default_str();
  cmd->add_option("--runs", args->o.runs, "Monte Carlo runs per scenario")
      ->capture_default_str()
      ->check(in_range(1, 10000));
  cmd->add_option("--files", args->o.files_dir, "Folder for the simulated track files (kept, for peers)")
      ->capture_default_str();
  cmd->add_flag("!--no-peer", args->o.peer, "Skip Stone Soup");
  cmd->add_option("--peer-script", args->o.peer_script, "The Stone Soup runner")->capture_default_str();
  cmd->add_option("--python", args->o.python, "Python with numpy, scipy and h5py (Debian's)")
      ->capture_default_str();
  finish_experiment_command(cmd, args, "SVG plot ('' = none)",
                            [](const RecordedExperimentOptions& o, std::ostream* progress) {
                              const auto rows = run_recorded_experiment(o, progress);
                              std::cout << recorded_summary_table(rows, o);
                              write_recorded_outputs(rows, o);
                            });
}

}  // namespace trackassoc::cli
