// trackassoc experiment seed003 [--model M.h5] [--data D.h5] [--output R.h5]: the seed 003 study
// (pair test metrics on the data set's test split; association accuracy and time vs track density,
// engine/studies/seed003/experiment_seed003.hpp run_seed003_study). Under mpirun its scenes are sharded
// over the ranks; rank 0 prints and writes.
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/studies/seed003/experiment_seed003.hpp"

namespace trackassoc::cli {

void register_experiment_seed003(CLI::App& experiment) {
  struct Args {
    CommonOptions common;
    Seed003StudyFiles files;
    Seed003ExperimentOptions options;
  };
  auto args = std::make_shared<Args>();
  args->common.seed = 3;
  args->files.model = TRACKASSOC_DATA_DIR "/models/siamese_seed003.h5";
  args->files.output = "seed003.h5";
  auto* cmd = experiment.add_subcommand(
      "seed003", "Seed 003 (TTCSN) study: pair test metrics and association vs track density");
  cmd->add_option("--model", args->files.model,
                  "Siamese model (from train-siamese; default: the shipped one)")
      ->capture_default_str();
  cmd->add_option("--lstm-model", args->files.lstm_model,
                  "Baseline: LSTM on concatenated pairs (train-siamese --architecture lstm)");
  cmd->add_option("--bilstm-model", args->files.bilstm_model,
                  "Baseline: BiLSTM on concatenated pairs (train-siamese --architecture bilstm)");
  cmd->add_option("--data", args->files.data,
                  "Data set: also report pair accuracy/recall/precision on its test split");
  cmd->add_option("--runs", args->options.runs, "Monte Carlo runs per density")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--densities", args->options.densities, "Track densities (targets per scene)")
      ->capture_default_str()
      ->check(in_range(1, 1e5));
  cmd->add_option("--threshold", args->options.probability_threshold, "TTCSN pair probability threshold")
      ->capture_default_str()
      ->check(in_range(0, 1, true, true));
  finish_study_command(cmd, args,
                       {.output = &args->files.output,
                        .output_help = "Result HDF5 file",
                        .sharded = true,
                        .inputs =
                            [args] {
                              const Seed003StudyFiles& f = args->files;
                              return std::vector<InputPath>{{f.model, "--model"},
                                                            {f.lstm_model, "--lstm-model"},
                                                            {f.bilstm_model, "--bilstm-model"},
                                                            {f.data, "--data"}};
                            }},
                       [args](std::ostream*, bool) {
                         Seed003ExperimentOptions o = args->options;
                         o.seed = args->common.seed;
                         const Seed003ExperimentResult r = run_seed003_study(args->files, o, std::cout);
                         if (!distributed::world().root()) return;  // rank 0 printed and wrote
                         std::cout << "results -> " << args->files.output << " (" << r.wall_time_s << " s)\n";
                       });
}

}  // namespace trackassoc::cli
