// trackassoc experiment seed002: Chen & Tong (2001), IMM {CS + BP network, CA} vs the CS-parallel
// filter, Table 1 and the sensitivity sweep (engine/studies/seed002/experiment_seed002.hpp). Under mpirun
// the motions of both are sharded over the ranks; rank 0 writes, prints and plots.
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/seed002/experiment_seed002.hpp"

namespace trackassoc::cli {

void register_experiment_seed002(CLI::App& experiment) {
  struct Args {
    Seed002Options options;
    CommonOptions common;
    std::string output = "seed002.h5", plots = "seed002-plots";
  };
  auto args = std::make_shared<Args>();
  args->common.seed = args->options.seed;
  auto* cmd = experiment.add_subcommand(
      "seed002", "Chen & Tong 2001: IMM {CS + network, CA} vs CS-parallel, RMSE curves and Table 1");
  cmd->add_option("--runs", args->options.runs, "Monte Carlo runs")
      ->capture_default_str()
      ->check(in_range(1, 1e6));
  cmd->add_option("--ca-sigma", args->options.models.ca_sigma, "σ of the IMM's CA model [m/s²] (paper: 5)")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--a-max", args->options.models.cs_a_max,
                  "a_max = −a_−max of the CS-parallel filter [m/s²] (not in the paper)")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_flag("--sensitivity", args->options.sensitivity,
                "Also sweep σ_CA × a_max (--sensitivity-ca-sigma, --sensitivity-a-max) with the same seeds");
  cmd->add_option("--sensitivity-ca-sigma", args->options.sensitivity_ca_sigma,
                  "σ_CA values of the sweep [m/s²]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--sensitivity-a-max", args->options.sensitivity_a_max, "a_max values of the sweep [m/s²]")
      ->capture_default_str()
      ->check(above(0));
  finish_study_command(
      cmd, args,
      {.output = &args->output,
       .output_help = "Output HDF5 file",
       .plots = &args->plots,
       .plots_help = "Folder for the PNG plots (scripts/plot.py)",
       .plots_is_folder = true,
       .sharded = true},
      [args](std::ostream* progress, bool plots) {
        args->options.seed = args->common.seed;
        args->options.validate();
        if (progress) *progress << "seed002: " << args->options.runs << " runs × 4 motions ...\n";
        auto& comm = distributed::world();
        const Seed002Result res = run_seed002(args->options, comm);
        if (!comm.root()) return;  // rank 0 has the motions, and alone writes and prints
        write_seed002(args->output, res);
        print_seed002(res, std::cout);
        if (!res.sensitivity.empty()) print_seed002_sensitivity(res, std::cout);
        std::cout << "\nwrote " << args->output << "\n";
        if (plots && run_plot_script("plot.py", {"seed002", args->output, "--outdir", args->plots}))
          std::cout << "plots in " << args->plots << "/\n";
      });
}

}  // namespace trackassoc::cli
