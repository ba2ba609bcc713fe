// The one way every `experiment` study registers (engine/cli/cmd_experiment*.cpp): its output
// and plot flags, --seed and --threads, the output-path check before any work, then one call.
#pragma once

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "engine/cli/common.hpp"

namespace trackassoc::cli {

// Where an `experiment` study writes: its result (--output, a file unless `output_is_folder`) and
// its plots (--plots, a file unless `plots_is_folder`; null when the study draws none), both
// members of the study's shared arguments.
struct StudyPaths {
  std::string* output = nullptr;
  std::string output_help = "HDF5 output";
  bool output_is_folder = false;
  std::string* plots = nullptr;
  std::string plots_help{};
  bool plots_is_folder = false;
};

// The one ending of every `experiment` study (engine/cli/cmd_experiment*.cpp): adds --output,-o,
// --plots and --no-plots (when the study plots), --seed and --threads; the callback limits the
// threads, checks the output paths before any work (io/atomic_file.hpp) and calls
// run(progress, plots): progress is std::cerr when it is a terminal (else null), plots is false
// under --no-plots. `Args` holds `CommonOptions common`.
template <class Args, class Run>
void finish_study_command(CLI::App* cmd, const std::shared_ptr<Args>& args, const StudyPaths& paths,
                          Run run) {
  add_output_option(cmd, *paths.output, paths.output_help)->capture_default_str();
  auto no_plots = std::make_shared<bool>(false);
  if (paths.plots) {
    cmd->add_option("--plots", *paths.plots, paths.plots_help)->capture_default_str();
    cmd->add_flag("--no-plots", *no_plots, "Draw no plots");
  }
  add_common_options(cmd, args->common);
  cmd->callback([args, paths, no_plots, run] {
    ThreadScope threads(args->common.threads);
    std::vector<OutputPath> outputs;  // checked before any work
    if (!paths.output_is_folder) outputs.push_back({*paths.output, "--output"});
    if (paths.plots && !paths.plots_is_folder && !*no_plots) outputs.push_back({*paths.plots, "--plots"});
    check_output_paths(outputs);
    run(isatty(STDERR_FILENO) ? &std::cerr : nullptr, paths.plots && !*no_plots);
  });
}

// The studies whose Options hold `output`, `plot` (an SVG path, "" = none) and `seed` (seed000,
// seed004, schedules, recorded): finish_study_command, then `run(options, progress)` prints the
// table and writes the files, and the command says what was written.
template <class Options>
struct ExperimentArgs {
  Options o;
  CommonOptions common;
};

template <class Options, class Run>
void finish_experiment_command(CLI::App* cmd, const std::shared_ptr<ExperimentArgs<Options>>& args,
                               const std::string& plot_help, Run run) {
  finish_study_command(cmd, args,
                       {.output = &args->o.output, .plots = &args->o.plot, .plots_help = plot_help},
                       [args, run](std::ostream* progress, bool plots) {
                         if (!plots) args->o.plot.clear();
                         args->o.seed = args->common.seed;
                         run(args->o, progress);
                         std::cout << "\nwrote " << args->o.output
                                   << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
                       });
}

}  // namespace trackassoc::cli
