// `trackassoc train-siamese`: trains a pair classifier of seed 003 (the Siamese BiLSTM TTCSN, or a
// baseline LSTM / BiLSTM on concatenated pairs, kernels/learning/siamese_training.hpp) on a data set of
// `trackassoc dataset seed003` and writes the model file (io/siamese_model_file.hpp).
//
// Split: the file's training pairs are already shuffled; the first `max_train_pairs` (0 = all)
// are kept and their last `validation_fraction` becomes the validation set (early stopping, and
// the close negatives among them for the reported rejection rate). Test metrics on the file's
// test split and on its close negatives alone. The model's training JSON records the data set,
// its generator, the shape, the training options and every metric (read back by experiment seed003).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "kernels/learning/siamese.hpp"
#include "kernels/learning/siamese_training.hpp"

namespace trackassoc {

struct TrainSiameseOptions {
  std::string data;                      // data set file (dataset seed003)
  std::string output;                    // model file
  std::string architecture = "siamese";  // siamese | lstm | bilstm
  SiameseShape shape;
  TrackNormalisation normalisation;
  SiameseTrainingOptions training;
  double validation_fraction = 0.1;  // in [0, 1)
  int64_t max_train_pairs = 0;       // 0 = all
};

struct TrainSiameseResult {
  SiameseTrainingSummary summary;
  PairEvaluation test, test_close, validation_close;
};

// Checks every option before reading the data set (InputError naming the option), trains, writes
// `output`, prints one progress line per epoch to `progress` and the summary to `out`.
TrainSiameseResult train_siamese_on_dataset(const TrainSiameseOptions& options, std::ostream& progress,
                                            std::ostream& out);

}  // namespace trackassoc
