// train-siamese (see train_siamese.hpp).
#include "engine/studies/seed003/train_siamese.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "engine/studies/seed003/dataset_seed003.hpp"
#include "io/atomic_file.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

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

// The pairs of `set` whose kind is a close negative (label 0).
PairSet close_negatives(const PairSet& set, const std::vector<uint8_t>& kind, std::size_t n) {
  PairSet close;
  for (std::size_t k = 0; k < n; ++k)
    if (kind[k] == static_cast<uint8_t>(PairKind::kCloseNegative)) {
      close.left.push_back(set.left[k]);
      close.right.push_back(set.right[k]);
      close.label.push_back(0);
    }
  return close;
}

}  // namespace

TrainSiameseResult train_siamese_on_dataset(const TrainSiameseOptions& a, std::ostream& progress,
                                            std::ostream& out) {
  // Every option is checked before the data set is read and before any progress line (issue 15);
  // the single ranges are the options' own (--validation-fraction in [0, 1), ...).
  SiameseModel<float> model;
  model.shape = a.shape;
  model.shape.architecture = parse_enum<PairArchitecture>(a.architecture, "architecture");
  model.normalisation = a.normalisation;
  model.normalisation.validate();
  model.shape.validate();
  const SiameseTrainingOptions& o = a.training;
  o.validate();
  check_output_paths({{a.output, "--output"}}, {{a.data, "--data"}});
  const Seed003Dataset d = read_seed003_dataset(a.data);
  // The file's training split is already shuffled: the last share becomes the validation set.
  PairSet train, validation, validation_close;  // the last: its close negatives (for model choice)
  std::size_t n = d.train.size();
  if (a.max_train_pairs > 0) n = std::min<std::size_t>(n, static_cast<std::size_t>(a.max_train_pairs));
  const std::size_t n_val = static_cast<std::size_t>(a.validation_fraction * double(n));
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
    throw InputError("--max-train-pairs " + std::to_string(a.max_train_pairs) + ", --validation-fraction " +
                     std::to_string(a.validation_fraction) + ": no training pairs left of " +
                     std::to_string(d.train.size()) + " in " + a.data);
  progress << "training " << a.architecture << " on " << train.size() << " pairs, validating on "
           << validation.size() << ", H = " << model.shape.hidden << ", fc = " << model.shape.fc << ", "
           << model.shape.parameter_count() << " parameters\n";
  TrainSiameseResult r;
  r.summary =
      train_siamese(model, d.radar1, d.radar2, train, validation, o, [&](const SiameseEpochReport& e) {
        char line[256];
        std::snprintf(line, sizeof line,
                      "epoch %3d  loss %.4f  val loss %.4f  val acc %6.2f %%  lr %.2e  %.1f s", e.epoch,
                      e.train_loss, e.validation.mean_loss, 100 * e.validation.accuracy(), e.learning_rate,
                      e.seconds);
        progress << line << "\n" << std::flush;
      });
  const SiameseTrainingSummary& summary = r.summary;
  r.test = evaluate_pairs(model, d.radar1, d.radar2, d.test);
  // Accuracy on the close negatives alone (the hard part of the test set).
  r.test_close =
      evaluate_pairs(model, d.radar1, d.radar2, close_negatives(d.test, d.test_kind, d.test.size()));
  r.validation_close = evaluate_pairs(model, d.radar1, d.radar2, validation_close);
  nlohmann::json j = {{"data", a.data},
                      {"generator", nlohmann::json::parse(d.generator_json, nullptr, false)},
                      {"architecture", a.architecture},
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
                      {"test", evaluation_json(r.test)},
                      {"validation_close_negatives_accuracy", r.validation_close.accuracy()},
                      {"test_close_negatives_accuracy", r.test_close.accuracy()}};
  write_siamese_model(a.output, model, j.dump());
  const PairEvaluation& val = summary.best_validation;
  out << "stopped: " << to_string(summary.termination) << " after " << summary.epochs_run
      << " epochs (best epoch " << summary.best_epoch << "), " << summary.wall_time_s << " s\n"
      << "validation pairs " << val.total() << ": accuracy " << percent(val.accuracy()) << ", recall "
      << percent(val.recall()) << ", precision " << percent(val.precision()) << "; close negatives rejected "
      << percent(r.validation_close.accuracy()) << "\n"
      << "test pairs " << r.test.total() << ": accuracy " << percent(r.test.accuracy()) << ", recall "
      << percent(r.test.recall()) << ", precision " << percent(r.test.precision())
      << " (seed 003: accuracy 99.1 %, recall > 99 %)\n"
      << "close negatives in the test set: " << r.test_close.total() << ", correctly rejected "
      << percent(r.test_close.accuracy()) << "\n"
      << "model -> " << a.output << "\n";
  return r;
}

}  // namespace trackassoc
