// trackassoc dataset seed003 --out D.h5: the seed 003 (TTCSN) pair data set.
// trackassoc train-siamese --data D.h5 --out model.h5: trains the Siamese BiLSTM, reports test metrics.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "engine/cli/common.hpp"
#include "engine/dataset_seed003.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/siamese_training.hpp"

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
  cmd->add_option("--out,-o", args->output, "Output HDF5 file")->required();
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
    check_output_paths({{args->output, "--out"}});
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

namespace {

std::string percent(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f %%", 100.0 * v);
  return b;
}

nlohmann::json evaluation_json(const PairEvaluation& e) {
  return {{"accuracy", e.accuracy()}, {"recall", e.recall()},  {"precision", e.precision()},
          {"mean_loss", e.mean_loss}, {"tp", e.true_positive}, {"tn", e.true_negative},
          {"fp", e.false_positive},   {"fn", e.false_negative}};
}

}  // namespace

void register_train_siamese(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string data, output;
    SiameseShape shape;
    SiameseTrainingOptions training;
    double validation_fraction = 0.1;
    int64_t max_train_pairs = 0;
    TrackNormalisation normalisation;
    std::string architecture = "siamese";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("train-siamese",
                                 "Train the Siamese BiLSTM pair classifier (seed 003) on a data set");
  cmd->add_option("--data", args->data, "Data set from `trackassoc dataset seed003`")->required();
  cmd->add_option("--out,-o", args->output, "Output model file (HDF5)")->required();
  cmd->add_option("--epochs", args->training.epochs, "Epoch limit")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--architecture", args->architecture,
                  "siamese (TTCSN), or the baselines on concatenated pairs: lstm, bilstm")
      ->check(CLI::IsMember({"siamese", "lstm", "bilstm"}))
      ->capture_default_str();
  cmd->add_option("--hidden", args->shape.hidden, "BiLSTM hidden units per direction")
      ->capture_default_str()
      ->check(in_range(1, 4096));
  cmd->add_option("--fc", args->shape.fc, "Width of the first dense layer")
      ->capture_default_str()
      ->check(in_range(1, 65536));
  cmd->add_option("--batch", args->training.batch_size, "Pairs per Adam step")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--lr", args->training.adam.learning_rate, "Adam learning rate")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--weight-decay", args->training.adam.weight_decay,
                  "Decoupled weight decay λ (AdamW; 0 = none)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--lr-decay", args->training.learning_rate_decay, "Learning-rate factor per epoch")
      ->capture_default_str()
      ->check(in_range(0, 1, true));
  cmd->add_option("--patience", args->training.patience,
                  "Epochs without validation improvement before stopping")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--augment-shift", args->training.augment_shift,
                  "Augmentation: translate each training pair by U(-a, a)^2 metres per epoch (0 = off)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--max-seconds", args->training.max_seconds, "Wall-time budget [s] (0 = none)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--validation-fraction", args->validation_fraction,
                  "Share of the training pairs held out for early stopping")
      ->capture_default_str()
      ->check(in_range(0, 1, false, true));
  cmd->add_option("--max-train-pairs", args->max_train_pairs, "Use only the first N training pairs (0 = all)")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--position-scale", args->normalisation.position_scale,
                  "Input normalisation: metres per unit of x and y (centre 50 km, 50 km)")
      ->capture_default_str()
      ->check(above(0));
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    // Every option is checked before the data set is read and before any progress line (issue 15);
    // the single ranges are the options' own (--validation-fraction in [0, 1), ...).
    SiameseModel<float> model;
    model.shape = args->shape;
    model.shape.architecture = parse_enum<PairArchitecture>(args->architecture, "architecture");
    model.normalisation = args->normalisation;
    model.normalisation.validate();
    model.shape.validate();
    SiameseTrainingOptions o = args->training;
    o.seed = args->common.seed;
    o.validate();
    check_output_paths({{args->output, "--out"}});
    const Seed003Dataset d = read_seed003_dataset(args->data);
    // The file's training split is already shuffled: the last share becomes the validation set.
    PairSet train, validation, validation_close;  // the last: its close negatives (for model choice)
    std::size_t n = d.train.size();
    if (args->max_train_pairs > 0)
      n = std::min<std::size_t>(n, static_cast<std::size_t>(args->max_train_pairs));
    const std::size_t n_val = static_cast<std::size_t>(args->validation_fraction * double(n));
    for (std::size_t k = 0; k < n; ++k) {
      PairSet& s = k < n - n_val ? train : validation;
      s.left.push_back(d.train.left[k]);
      s.right.push_back(d.train.right[k]);
      s.label.push_back(d.train.label[k]);
      if (&s == &validation && d.train_kind[k] == static_cast<uint8_t>(PairKind::kCloseNegative)) {
        validation_close.left.push_back(d.train.left[k]);
        validation_close.right.push_back(d.train.right[k]);
        validation_close.label.push_back(0);
      }
    }
    if (train.size() == 0)
      throw InputError("--max-train-pairs " + std::to_string(args->max_train_pairs) +
                       ", --validation-fraction " + std::to_string(args->validation_fraction) +
                       ": no training pairs left of " + std::to_string(d.train.size()) + " in " + args->data);
    const bool tty = isatty(fileno(stderr));
    std::cerr << "training " << args->architecture << " on " << train.size() << " pairs, validating on "
              << validation.size() << ", H = " << model.shape.hidden << ", fc = " << model.shape.fc << ", "
              << model.shape.parameter_count() << " parameters\n";
    const auto summary =
        train_siamese(model, d.radar1, d.radar2, train, validation, o, [&](const SiameseEpochReport& r) {
          char line[256];
          std::snprintf(line, sizeof line,
                        "epoch %3d  loss %.4f  val loss %.4f  val acc %6.2f %%  lr %.2e  %.1f s", r.epoch,
                        r.train_loss, r.validation.mean_loss, 100 * r.validation.accuracy(), r.learning_rate,
                        r.seconds);
          std::cerr << line << (tty ? "\n" : "\n") << std::flush;
        });
    const PairEvaluation test = evaluate_pairs(model, d.radar1, d.radar2, d.test);
    // Accuracy on the close negatives alone (the hard part of the test set).
    PairSet close;
    for (std::size_t k = 0; k < d.test.size(); ++k)
      if (d.test_kind[k] == static_cast<uint8_t>(PairKind::kCloseNegative)) {
        close.left.push_back(d.test.left[k]);
        close.right.push_back(d.test.right[k]);
        close.label.push_back(0);
      }
    const PairEvaluation close_ev = evaluate_pairs(model, d.radar1, d.radar2, close);
    const PairEvaluation val_close_ev = evaluate_pairs(model, d.radar1, d.radar2, validation_close);
    nlohmann::json j = {{"data", args->data},
                        {"generator", nlohmann::json::parse(d.generator_json, nullptr, false)},
                        {"architecture", args->architecture},
                        {"hidden", model.shape.hidden},
                        {"fc", model.shape.fc},
                        {"position_scale", model.normalisation.position_scale},
                        {"epochs_limit", o.epochs},
                        {"batch", o.batch_size},
                        {"augment_shift_m", o.augment_shift},
                        {"learning_rate", o.adam.learning_rate},
                        {"learning_rate_decay", o.learning_rate_decay},
                        {"weight_decay", o.adam.weight_decay},
                        {"seed", o.seed},
                        {"train_pairs", train.size()},
                        {"validation_pairs", validation.size()},
                        {"termination", to_string(summary.termination)},
                        {"epochs_run", summary.epochs_run},
                        {"best_epoch", summary.best_epoch},
                        {"wall_time_s", summary.wall_time_s},
                        {"validation", evaluation_json(summary.best_validation)},
                        {"test", evaluation_json(test)},
                        {"validation_close_negatives_accuracy", val_close_ev.accuracy()},
                        {"test_close_negatives_accuracy", close_ev.accuracy()}};
    write_siamese_model(args->output, model, j.dump());
    const PairEvaluation& val = summary.best_validation;
    std::cout << "stopped: " << to_string(summary.termination) << " after " << summary.epochs_run
              << " epochs (best epoch " << summary.best_epoch << "), " << summary.wall_time_s << " s\n"
              << "validation pairs " << val.total() << ": accuracy " << percent(val.accuracy()) << ", recall "
              << percent(val.recall()) << ", precision " << percent(val.precision())
              << "; close negatives rejected " << percent(val_close_ev.accuracy()) << "\n"
              << "test pairs " << test.total() << ": accuracy " << percent(test.accuracy()) << ", recall "
              << percent(test.recall()) << ", precision " << percent(test.precision())
              << " (seed 003: accuracy 99.1 %, recall > 99 %)\n"
              << "close negatives in the test set: " << close_ev.total() << ", correctly rejected "
              << percent(close_ev.accuracy()) << "\n"
              << "model -> " << args->output << "\n";
  });
}

}  // namespace trackassoc::cli
