// Training and evaluation of the Siamese BiLSTM pair classifier (seed 003 §3.1: binary
// cross-entropy on labelled track pairs, 70/30 split).
//
// Mini-batch Adam (adam.hpp). Each mini-batch is cut into fixed chunks of `chunk_pairs` pairs; the
// chunks run as TBB tasks, each into its own gradient buffer, and the buffers are summed in chunk
// order. The chunking does not depend on the thread count, so a training run is bit-identical for
// 1 and 2 threads (tests/kernels/learning/test_siamese_training.cpp). The pair order of epoch e is a
// Fisher–Yates shuffle from CounterRng(seed, e, stream 5).
//
// Early stopping: after every epoch the validation loss is computed; training stops when it has not
// improved by a relative `min_improvement` for `patience` epochs (a plateau), and the weights of the
// best epoch are restored. Cost per epoch: O(pairs · T · 4H(F+H)) for the branch, forward and back.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/learning/adam.hpp"
#include "kernels/learning/siamese.hpp"

namespace trackassoc {

struct SiameseTrainingOptions {
  int epochs = 40;       // epoch limit
  int batch_size = 64;   // pairs per Adam step
  int chunk_pairs = 16;  // pairs per TBB task (fixed: determinism does not depend on threads)
  AdamOptions adam{2e-3, 0.9, 0.999, 1e-8, 5.0};
  double learning_rate_decay = 0.93;  // α multiplied by this after every epoch
  int patience = 5;                   // epochs without validation-loss improvement before stopping
  double min_improvement = 1e-3;      // relative improvement that counts
  double max_seconds = 0.0;           // wall-time budget; 0 = none
  uint64_t seed = 1;                  // initialisation (if the model is empty) and shuffling
  // Data augmentation against over-fitting: each training pair is translated as a whole (both
  // tracks by the same vector, so its label is unchanged) by U(−a, a)² metres, drawn afresh every
  // epoch from CounterRng(seed, epoch, chunk). 0 = off (the paper's fixed data set).
  double augment_shift = 0.0;  // a [m]
  void validate() const;
};

enum class TrainingTermination { kEpochLimit, kPlateau, kTimeLimit };
const char* to_string(TrainingTermination t);

struct PairEvaluation {
  double mean_loss = 0.0;
  int64_t true_positive = 0, true_negative = 0, false_positive = 0, false_negative = 0;
  int64_t total() const { return true_positive + true_negative + false_positive + false_negative; }
  double accuracy() const { return total() ? double(true_positive + true_negative) / double(total()) : 0.0; }
  double recall() const {
    return true_positive + false_negative ? double(true_positive) / double(true_positive + false_negative)
                                          : 0.0;
  }
  double precision() const {
    return true_positive + false_positive ? double(true_positive) / double(true_positive + false_positive)
                                          : 0.0;
  }
};

struct SiameseEpochReport {
  int epoch = 0;
  double train_loss = 0.0;  // mean BCE over the epoch's mini-batches
  PairEvaluation validation;
  double learning_rate = 0.0;
  double seconds = 0.0;  // wall time of the epoch, including validation
};

struct SiameseTrainingSummary {
  TrainingTermination termination = TrainingTermination::kEpochLimit;
  int epochs_run = 0;
  int best_epoch = 0;  // 1-based; its weights are the ones left in the model
  PairEvaluation best_validation;
  double wall_time_s = 0.0;
  std::vector<SiameseEpochReport> history;
};

// Scratch buffers of siamese_minibatch_step, reused across steps.
template <class S>
struct SiameseStepWorkspace {
  std::vector<AlignedVector<S>> chunk_grad;
  std::vector<double> chunk_loss;
  AlignedVector<S> grad;
};

// One Adam step on the mini-batch of pairs (l[k], r[k]) with labels y[k]: chunks of `chunk_pairs`
// pairs across TBB, gradients summed in chunk order, averaged, then adam_step. Returns the summed
// BCE of the mini-batch (before the step). With augment_shift > 0, every pair of chunk c is translated
// by a vector drawn from CounterRng(augment_key, c) (see SiameseTrainingOptions::augment_shift).
template <class S>
double siamese_minibatch_step(SiameseModel<S>& model, const TrackSequences& left, const TrackSequences& right,
                              std::span<const int32_t> l, std::span<const int32_t> r,
                              std::span<const uint8_t> y, int chunk_pairs, AdamState<S>& adam,
                              const AdamOptions& adam_options, SiameseStepWorkspace<S>& workspace,
                              double augment_shift = 0.0, uint64_t augment_key = 0);

// Adds the translation (dx, dy) [m] of pair b to the valid steps of its column(s) of a model pair batch.
template <class S>
void translate_pair(const SiameseModel<S>& model, SequenceBatch<S>& batch, int pair, double dx, double dy);

// Probabilities (or nothing) and the confusion counts at `threshold` for a pair set.
template <class S>
PairEvaluation evaluate_pairs(const SiameseModel<S>& model, const TrackSequences& left,
                              const TrackSequences& right, const PairSet& pairs, double threshold = 0.5,
                              std::vector<double>* probabilities = nullptr);

// Trains `model` in place (initialised from options.seed when model.params is empty).
// on_epoch is called after every epoch (progress display lives in the caller).
template <class S>
SiameseTrainingSummary train_siamese(SiameseModel<S>& model, const TrackSequences& left,
                                     const TrackSequences& right, const PairSet& train,
                                     const PairSet& validation, const SiameseTrainingOptions& options,
                                     const std::function<void(const SiameseEpochReport&)>& on_epoch = {});

// Checks that every pair indexes existing tracks and labels are 0/1; throws InputError naming `name`.
void validate_pairs(const PairSet& pairs, const TrackSequences& left, const TrackSequences& right,
                    const char* name);

}  // namespace trackassoc
