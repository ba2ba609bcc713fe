// trackassoc dataset seed003 --output D.h5: the seed 003 (TTCSN) pair data set.
// trackassoc train-siamese --data D.h5 --output model.h5: trains the Siamese BiLSTM, reports test
// metrics (engine/studies/seed003/train_siamese.hpp).
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "engine/cli/common.hpp"
#include "engine/studies/seed003/dataset_seed003.hpp"
#include "engine/studies/seed003/train_siamese.hpp"

namespace trackassoc::cli {

void register_dataset(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string name, output;
    Seed003Options options;
    std::vector<double> radar1, radar2;
    std::string close_measure = "start";
  };
  auto args = std::make_shared<Args>();
  args->common.seed = args->options.seed;
  args->radar1 = {args->options.radar1_x, args->options.radar1_y};
  args->radar2 = {args->options.radar2_x, args->options.radar2_y};
  auto* cmd =
      app.add_subcommand("dataset", "Generate a paper's training data set (HDF5): seed003 (TTCSN pairs)");
  cmd->add_option("name", args->name, "Data set name")->required()->check(CLI::IsMember({"seed003"}));
  add_output_option(cmd, args->output, "Output HDF5 file")->required();
  cmd->add_option("--targets", args->options.targets, "Number of targets")
      ->capture_default_str()
      ->check(in_range(2, 1e7));
  cmd->add_option("--positives", args->options.positives, "Positive pairs (<= targets)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--random-negatives", args->options.random_negatives, "Random negative pairs")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--close-negatives", args->options.close_negatives, "Close-but-different negative pairs")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--close-distance", args->options.close_distance,
                  "Distance below which a different target is close [m] (see --close-measure)")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--max-heading-change", args->options.max_heading_change,
                  "Heading change bound per second [rad]")
      ->capture_default_str()
      ->check(in_range(0, std::numbers::pi));
  cmd->add_option("--max-speed-change", args->options.max_speed_change, "Speed change bound per second [m/s]")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option(
         "--close-measure", args->close_measure,
         "Close negatives: start (true distance at t = 0) or mean (mean true distance over the flight)")
      ->check(CLI::IsMember({"mean", "start"}))
      ->capture_default_str();
  cmd->add_option("--radar1", args->radar1, "Radar 1 position x y [m]")
      ->expected(2)
      ->capture_default_str()
      ->check(in_range(-kInf, kInf));
  cmd->add_option("--radar2", args->radar2, "Radar 2 position x y [m]")
      ->expected(2)
      ->capture_default_str()
      ->check(in_range(-kInf, kInf));
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    Seed003Options o = args->options;
    o.seed = args->common.seed;
    o.radar1_x = args->radar1[0], o.radar1_y = args->radar1[1];
    o.radar2_x = args->radar2[0], o.radar2_y = args->radar2[1];
    o.close_measure =
        args->close_measure == "start" ? CloseMeasure::kStartDistance : CloseMeasure::kMeanDistance;
    check_output_paths({{args->output, "--output"}});
    const Seed003Dataset d = generate_seed003_dataset(o);
    write_seed003_dataset(args->output, d);
    const auto j = nlohmann::json::parse(d.generator_json);
    std::cout << "seed003 data set: " << d.radar1.size() << " targets, " << d.radar1.x.size() << " + "
              << d.radar2.x.size() << " plots, " << d.train.size() << " training and " << d.test.size()
              << " test pairs (close negatives found: " << j["close_negatives_found"].get<int>() << " of "
              << o.close_negatives << "; targets with a close partner: " << j["close_candidates"].get<int>()
              << ") -> " << args->output << "\n";
  });
}

void register_train_siamese(CLI::App& app) {
  struct Args {
    CommonOptions common;
    TrainSiameseOptions o;
  };
  auto args = std::make_shared<Args>();
  TrainSiameseOptions& o = args->o;
  auto* cmd = app.add_subcommand("train-siamese",
                                 "Train the Siamese BiLSTM pair classifier (seed 003) on a data set");
  cmd->add_option("--data", o.data, "Data set from `trackassoc dataset seed003`")->required();
  add_output_option(cmd, o.output, "Output model file (HDF5)")->required();
  cmd->add_option("--epochs", o.training.epochs, "Epoch limit")->capture_default_str()->check(at_least(1));
  cmd->add_option("--architecture", o.architecture,
                  "siamese (TTCSN), or the baselines on concatenated pairs: lstm, bilstm")
      ->check(enum_choices<PairArchitecture>())
      ->capture_default_str();
  cmd->add_option("--hidden", o.shape.hidden, "BiLSTM hidden units per direction")
      ->capture_default_str()
      ->check(in_range(1, 4096));
  cmd->add_option("--fc", o.shape.fc, "Width of the first dense layer")
      ->capture_default_str()
      ->check(in_range(1, 65536));
  cmd->add_option("--batch", o.training.batch_size, "Pairs per Adam step")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--lr", o.training.adam.learning_rate, "Adam learning rate")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--weight-decay", o.training.adam.weight_decay,
                  "Decoupled weight decay λ (AdamW; 0 = none)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--lr-decay", o.training.learning_rate_decay, "Learning-rate factor per epoch")
      ->capture_default_str()
      ->check(in_range(0, 1, true));
  cmd->add_option("--patience", o.training.patience, "Epochs without validation improvement before stopping")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--augment-shift", o.training.augment_shift,
                  "Augmentation: translate each training pair by U(-a, a)^2 metres per epoch (0 = off)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--max-seconds", o.training.max_seconds, "Wall-time budget [s] (0 = none)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--validation-fraction", o.validation_fraction,
                  "Share of the training pairs held out for early stopping")
      ->capture_default_str()
      ->check(in_range(0, 1, false, true));
  cmd->add_option("--max-train-pairs", o.max_train_pairs, "Use only the first N training pairs (0 = all)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--position-scale", o.normalisation.position_scale,
                  "Input normalisation: metres per unit of x and y (centre 50 km, 50 km)")
      ->capture_default_str()
      ->check(above(0));
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    TrainSiameseOptions o = args->o;
    o.training.seed = args->common.seed;
    train_siamese_on_dataset(o, std::cerr, std::cout);
  });
}

}  // namespace trackassoc::cli
