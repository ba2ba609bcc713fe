// The one way every `experiment` study registers (engine/cli/cmd_experiment*.cpp): its output
// and plot flags, --seed and --threads, the output-path check before any work, then one call.
#pragma once

#include <functional>
#include <iostream>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "engine/cli/common.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/distributed/sharding.hpp"

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
  // The study shards its runs over MPI ranks (engine/distributed/sharding.hpp, sharded_items);
  // a study that does not is refused under more than one rank rather than run N times.
  bool sharded = false;
  // The study's input files ({path, option}; "" = not given), read when the command runs: no
  // output may be one of them (io/atomic_file.hpp, check_output_paths).
  std::function<std::vector<InputPath>()> inputs{};
};

// The inputs of a --scenarios list: its entries that are files (the others are embedded names).
inline std::vector<InputPath> scenario_inputs(const std::vector<std::string>& scenarios) {
  std::vector<InputPath> inputs;
  for (const std::string& s : scenarios) inputs.push_back({s, "--scenarios"});
  return inputs;
}

// The `experiment` studies that shard their runs over MPI ranks (filled as they register; main.cpp
// refuses every other study under more than one rank before it parses its flags).
inline std::set<std::string>& sharded_studies() {
  static std::set<std::string> names;
  return names;
}

// The one ending of every `experiment` study (engine/cli/cmd_experiment*.cpp): adds --output,-o,
// --plots and --no-plots (when the study plots), --seed and --threads; the callback limits the
// threads, checks the output paths before any work (io/atomic_file.hpp) and calls
// run(progress, plots): progress is std::cerr when it is a terminal (else null), plots is false
// under --no-plots. `Args` holds `CommonOptions common`.
template <class Args, class Run>
void finish_study_command(CLI::App* cmd, const std::shared_ptr<Args>& args, const StudyPaths& paths,
                          Run run) {
  add_output_option(cmd, *paths.output, paths.output_help)->capture_default_str();
  if (paths.sharded) sharded_studies().insert(cmd->get_name());
  auto no_plots = std::make_shared<bool>(false);
  if (paths.plots) {
    cmd->add_option("--plots", *paths.plots, paths.plots_help)->capture_default_str();
    cmd->add_flag("--no-plots", *no_plots, "Draw no plots");
  }
  add_common_options(cmd, args->common);
  cmd->callback([args, paths, no_plots, run, name = cmd->get_name()] {
    ThreadScope threads(args->common.threads);
    auto& comm = distributed::world();
    if (comm.size() > 1 && !paths.sharded)
      throw InputError("experiment " + name + ": not sharded over MPI ranks; run it as one process (got " +
                       std::to_string(comm.size()) + " ranks)");
    std::vector<OutputPath> outputs;  // checked before any work, by rank 0, which alone writes
    if (!paths.output_is_folder) outputs.push_back({*paths.output, "--output"});
    if (paths.plots && !paths.plots_is_folder && !*no_plots) outputs.push_back({*paths.plots, "--plots"});
    distributed::check_on_root(
        comm, [&] { check_output_paths(outputs, paths.inputs ? paths.inputs() : std::vector<InputPath>{}); });
    run(isatty(STDERR_FILENO) && comm.root() ? &std::cerr : nullptr, paths.plots && !*no_plots);
  });
}

// The studies whose Options hold `output`, `plot` (an SVG path, "" = none) and `seed` (seed000,
// seed004, schedules, recorded): finish_study_command, then `run(options, progress)` prints the
// table and writes the files, and the command says what was written. With `sharded`, `run` is
// called on every rank and must return on the ranks other than 0 once its runs are gathered
// (distributed::world().root()); the closing line is rank 0's.
template <class Options>
struct ExperimentArgs {
  Options o;
  CommonOptions common;
};

template <class Options, class Run>
void finish_experiment_command(CLI::App* cmd, const std::shared_ptr<ExperimentArgs<Options>>& args,
                               const std::string& plot_help, Run run, bool sharded = false) {
  std::function<std::vector<InputPath>()> inputs;
  if constexpr (requires(Options & o) { o.scenarios; })  // the scenario JSON files of --scenarios
    inputs = [args] { return scenario_inputs(args->o.scenarios); };
  finish_study_command(cmd, args,
                       {.output = &args->o.output,
                        .plots = &args->o.plot,
                        .plots_help = plot_help,
                        .sharded = sharded,
                        .inputs = inputs},
                       [args, run](std::ostream* progress, bool plots) {
                         if (!plots) args->o.plot.clear();
                         args->o.seed = args->common.seed;
                         run(args->o, progress);
                         if (!distributed::world().root()) return;
                         std::cout << "\nwrote " << args->o.output
                                   << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
                       });
}

}  // namespace trackassoc::cli
