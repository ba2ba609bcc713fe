// trackassoc experiment seed001: fuzzy association with temporary tracks and reliabilities against
// FTAA (seed 001 §4, engine/studies/seed001/experiment_seed001.hpp). Prints Table 1–2 beside the paper's for
// both readings of σθ₁ (0.1°, the erratum and default, and 1° as printed), with a reason per row, writes run
// 0 of the selected reading and the RMSE curves to HDF5 (run_seed001_study), and plots with scripts/plot.py.
// Under mpirun the runs of both readings are sharded over the ranks; rank 0 prints, writes and plots.
#include <iostream>
#include <string>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/seed001/experiment_seed001.hpp"

namespace trackassoc::cli {

void register_experiment_seed001(CLI::App& experiment) {
  struct Args {
    CommonOptions common;
    Seed001Options options;
    std::string output = "seed001.h5", plots, packets = "plot", reading = "erratum";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = experiment.add_subcommand("seed001",
                                        "Seed 001: fuzzy association with temporary tracks and "
                                        "reliabilities vs FTAA, 4 sensors, two crossing targets");
  cmd->add_option("--runs", args->options.runs, "Monte Carlo runs")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--duration", args->options.duration, "Scenario duration [s]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--packet-period", args->options.packet_period,
                  "Local node report period T [s] (sensors scan every 1 s)")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--sigma-bearing-reading", args->reading,
                  "Node 1's bearing σ: erratum (0.1°, consistent with the reliabilities) or literal (1° as "
                  "printed). The table shows both; this one is written to --output")
      ->check(enum_choices<BearingReading>())
      ->capture_default_str();
  auto* packets = cmd->add_option("--packets", args->packets,
                                  "Packet content: plot (one converted measurement, the paper's) or track "
                                  "(the local track's Kalman estimate)");
  packets->check(enum_choices<PacketSource>())->capture_default_str();
  cmd->add_option("--smoother-process-noise", args->options.smoother_process_noise,
                  "σ_w of the α-β (Kalata) design of the system tracks [m/s²]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--timeout", args->options.fuzzy.track_timeout,
                  "Proposed method: drop a system track not updated for this long [s] (0 = never)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--gate", args->options.fuzzy.gate, "Tracking gate radius [m] (both methods)")
      ->capture_default_str()
      ->check(above(0));
  finish_study_command(cmd, args,
                       {.output = &args->output,
                        .output_help = "Output HDF5 file (run 0 and the RMSE curves)",
                        .plots = &args->plots,
                        .plots_help = "Folder for the plots (runs scripts/plot.py seed001; empty = none)",
                        .plots_is_folder = true,
                        .sharded = true},
                       [args](std::ostream*, bool plots) {
                         Seed001Options o = args->options;
                         o.seed = args->common.seed;
                         o.ftaa.gate = o.fuzzy.gate;
                         o.packet_source = parse_enum<PacketSource>(args->packets, "--packets");
                         o.bearing_reading =
                             parse_enum<BearingReading>(args->reading, "--sigma-bearing-reading");
                         run_seed001_study(o, args->output, std::cout);
                         if (!distributed::world().root()) return;  // rank 0 wrote the file
                         if (plots && !args->plots.empty())
                           run_plot_script("plot.py", {"seed001", args->output, "--outdir", args->plots});
                       });
}

}  // namespace trackassoc::cli
