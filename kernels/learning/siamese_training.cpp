// Training and evaluation of the Siamese BiLSTM (see siamese_training.hpp).
#include "kernels/learning/siamese_training.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {

void SiameseTrainingOptions::validate() const {
  require(epochs >= 1, "SiameseTrainingOptions.epochs", "must be >= 1, got " + std::to_string(epochs));
  require(batch_size >= 1, "SiameseTrainingOptions.batch_size",
          "must be >= 1, got " + std::to_string(batch_size));
  require(chunk_pairs >= 1, "SiameseTrainingOptions.chunk_pairs",
          "must be >= 1, got " + std::to_string(chunk_pairs));
  adam.validate();
  require(learning_rate_decay > 0 && learning_rate_decay <= 1, "SiameseTrainingOptions.learning_rate_decay",
          "must be in (0, 1], got " + std::to_string(learning_rate_decay));
  require(patience >= 1, "SiameseTrainingOptions.patience", "must be >= 1, got " + std::to_string(patience));
  require(min_improvement >= 0 && std::isfinite(min_improvement), "SiameseTrainingOptions.min_improvement",
          "must be finite and >= 0");
  require(augment_shift >= 0 && std::isfinite(augment_shift), "SiameseTrainingOptions.augment_shift",
          "must be finite and >= 0");
  require(max_seconds >= 0 && std::isfinite(max_seconds), "SiameseTrainingOptions.max_seconds",
          "must be finite and >= 0");
}

const char* to_string(TrainingTermination t) {
  switch (t) {
    case TrainingTermination::kEpochLimit:
      return "epoch_limit";
    case TrainingTermination::kPlateau:
      return "plateau";
    case TrainingTermination::kTimeLimit:
      return "time_limit";
  }
  return "unknown";
}

void validate_pairs(const PairSet& pairs, const TrackSequences& left, const TrackSequences& right,
                    const char* name) {
  const std::string where(name);
  require(pairs.left.size() == pairs.size() && pairs.right.size() == pairs.size(), where,
          "left, right and label must have equal lengths");
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    require(pairs.left[k] >= 0 && pairs.left[k] < left.size(), where + ".left",
            "pair " + std::to_string(k) + " refers to track " + std::to_string(pairs.left[k]) + " of " +
                std::to_string(left.size()));
    require(pairs.right[k] >= 0 && pairs.right[k] < right.size(), where + ".right",
            "pair " + std::to_string(k) + " refers to track " + std::to_string(pairs.right[k]) + " of " +
                std::to_string(right.size()));
    require(pairs.label[k] <= 1, where + ".label",
            "pair " + std::to_string(k) + " has label " + std::to_string(int(pairs.label[k])) +
                ", expected 0 or 1");
  }
}

template <class S>
PairEvaluation evaluate_pairs(const SiameseModel<S>& model, const TrackSequences& left,
                              const TrackSequences& right, const PairSet& pairs, double threshold,
                              std::vector<double>* probabilities) {
  const std::size_t n = pairs.size();
  std::vector<double> logits(n);
  constexpr std::size_t kChunk = 128;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  parallel_for_range(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    VectorX<S> z;
    for (std::size_t c = cb; c < ce; ++c) {
      const std::size_t b = c * kChunk, e = std::min(n, b + kChunk);
      const std::span<const int32_t> l(pairs.left.data() + b, e - b), r(pairs.right.data() + b, e - b);
      siamese_pair_logits(model, make_model_pair_batch<S>(model, left, l, right, r), z);
      for (std::size_t k = b; k < e; ++k)
        logits[k] = static_cast<double>(z[static_cast<Eigen::Index>(k - b)]);
    }
  });
  PairEvaluation ev;
  double loss = 0;
  if (probabilities) probabilities->resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    loss += binary_cross_entropy_from_logit(logits[k], pairs.label[k]);
    const double p = 1.0 / (1.0 + std::exp(-logits[k]));
    if (probabilities) (*probabilities)[k] = p;
    const bool predicted = p >= threshold, actual = pairs.label[k] == 1;
    if (predicted && actual)
      ++ev.true_positive;
    else if (predicted)
      ++ev.false_positive;
    else if (actual)
      ++ev.false_negative;
    else
      ++ev.true_negative;
  }
  ev.mean_loss = n ? loss / double(n) : 0.0;
  return ev;
}

template <class S>
void translate_pair(const SiameseModel<S>& model, SequenceBatch<S>& batch, int pair, double dx, double dy) {
  const S sx = static_cast<S>(dx / model.normalisation.position_scale);
  const S sy = static_cast<S>(dy / model.normalisation.position_scale);
  const bool siamese = model.shape.architecture == PairArchitecture::kSiamese;
  const int B = siamese ? batch.batch() / 2 : batch.batch();
  for (int col : {pair, siamese ? pair + B : -1}) {
    if (col < 0) continue;
    for (int t = 0; t < batch.length(); ++t)
      if (batch.mask(t, col) != S(0)) {
        batch.steps[t](0, col) += sx;
        batch.steps[t](1, col) += sy;
      }
  }
}

template <class S>
double siamese_minibatch_step(SiameseModel<S>& model, const TrackSequences& left, const TrackSequences& right,
                              std::span<const int32_t> l, std::span<const int32_t> r,
                              std::span<const uint8_t> y, int chunk_pairs, AdamState<S>& adam,
                              const AdamOptions& adam_options, SiameseStepWorkspace<S>& ws,
                              double augment_shift, uint64_t augment_key) {
  const std::size_t P = model.params.size();
  const std::size_t m = y.size();
  const std::size_t cp = static_cast<std::size_t>(std::max(1, chunk_pairs));
  const std::size_t chunks = (m + cp - 1) / cp;
  if (ws.chunk_grad.size() < chunks) ws.chunk_grad.resize(chunks);
  ws.chunk_loss.resize(std::max(ws.chunk_loss.size(), chunks));
  for (std::size_t c = 0; c < chunks; ++c) ws.chunk_grad[c].resize(P);
  ws.grad.resize(P);
  parallel_for_range(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c) {
      const std::size_t s = c * cp, e = std::min(m, s + cp);
      std::fill(ws.chunk_grad[c].begin(), ws.chunk_grad[c].end(), S(0));
      auto batch = make_model_pair_batch<S>(model, left, l.subspan(s, e - s), right, r.subspan(s, e - s));
      if (augment_shift > 0) {
        CounterRng rng(augment_key, c, 6);
        for (std::size_t k = 0; k < e - s; ++k)
          translate_pair(model, batch, static_cast<int>(k), rng.uniform(-augment_shift, augment_shift),
                         rng.uniform(-augment_shift, augment_shift));
      }
      ws.chunk_loss[c] =
          siamese_loss_and_gradient(model, batch, y.subspan(s, e - s), ws.chunk_grad[c].data(), nullptr);
    }
  });
  // Sum the chunks in order (deterministic for any thread count), as the gradient of the MEAN loss.
  std::fill(ws.grad.begin(), ws.grad.end(), S(0));
  double loss = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    loss += ws.chunk_loss[c];
    const S* g = ws.chunk_grad[c].data();
    for (std::size_t k = 0; k < P; ++k) ws.grad[k] += g[k];
  }
  const S inv_m = S(1) / static_cast<S>(m);
  for (auto& g : ws.grad) g *= inv_m;
  adam_step<S>(model.params, ws.grad, adam, adam_options);
  return loss;
}

template <class S>
SiameseTrainingSummary train_siamese(SiameseModel<S>& model, const TrackSequences& left,
                                     const TrackSequences& right, const PairSet& train,
                                     const PairSet& validation, const SiameseTrainingOptions& options,
                                     const std::function<void(const SiameseEpochReport&)>& on_epoch) {
  using clock = std::chrono::steady_clock;
  options.validate();
  model.shape.validate();
  model.normalisation.validate();
  left.validate("left tracks");
  right.validate("right tracks");
  validate_pairs(train, left, right, "training pairs");
  validate_pairs(validation, left, right, "validation pairs");
  require(train.size() > 0, "training pairs", "must not be empty");
  if (model.params.empty()) siamese_initialise(model, options.seed);
  require(static_cast<int64_t>(model.params.size()) == model.shape.parameter_count(), "model",
          "has " + std::to_string(model.params.size()) + " parameters, its shape needs " +
              std::to_string(model.shape.parameter_count()));

  const auto start = clock::now();
  const std::size_t n = train.size();
  SiameseStepWorkspace<S> workspace;
  std::vector<uint32_t> order(n);
  std::vector<int32_t> bl, br;
  std::vector<uint8_t> by;
  AdamState<S> adam;
  AdamOptions adam_options = options.adam;

  SiameseTrainingSummary summary;
  AlignedVector<S> best_params = model.params;
  double best_loss = std::numeric_limits<double>::infinity();
  int since_best = 0;
  for (int epoch = 1; epoch <= options.epochs; ++epoch) {
    const auto epoch_start = clock::now();
    std::iota(order.begin(), order.end(), 0u);
    CounterRng rng(options.seed, static_cast<uint64_t>(epoch), 5);
    rng.shuffle(std::span<uint32_t>(order));
    double epoch_loss = 0;
    for (std::size_t b0 = 0; b0 < n; b0 += static_cast<std::size_t>(options.batch_size)) {
      const std::size_t b1 = std::min(n, b0 + static_cast<std::size_t>(options.batch_size));
      bl.clear(), br.clear(), by.clear();
      for (std::size_t k = b0; k < b1; ++k) {
        bl.push_back(train.left[order[k]]);
        br.push_back(train.right[order[k]]);
        by.push_back(train.label[order[k]]);
      }
      epoch_loss += siamese_minibatch_step<S>(model, left, right, bl, br, by, options.chunk_pairs, adam,
                                              adam_options, workspace, options.augment_shift,
                                              stream_key(options.seed, static_cast<uint64_t>(epoch), b0, 7));
    }
    SiameseEpochReport report;
    report.epoch = epoch;
    report.train_loss = epoch_loss / double(n);
    report.learning_rate = adam_options.learning_rate;
    report.validation = validation.size() ? evaluate_pairs(model, left, right, validation)
                                          : evaluate_pairs(model, left, right, train);
    report.seconds = std::chrono::duration<double>(clock::now() - epoch_start).count();
    summary.history.push_back(report);
    summary.epochs_run = epoch;
    if (on_epoch) on_epoch(report);
    adam_options.learning_rate *= options.learning_rate_decay;

    const double vloss = report.validation.mean_loss;
    const bool significant = vloss < best_loss * (1.0 - options.min_improvement);
    if (vloss <
        best_loss) {  // any improvement updates the kept weights; only a significant one resets patience
      best_loss = vloss;
      best_params = model.params;
      summary.best_epoch = epoch;
      summary.best_validation = report.validation;
    }
    since_best = significant ? 0 : since_best + 1;
    if (since_best >= options.patience && epoch < options.epochs) {  // at the limit it is the limit
      summary.termination = TrainingTermination::kPlateau;
      break;
    }
    const double elapsed = std::chrono::duration<double>(clock::now() - start).count();
    if (options.max_seconds > 0 && elapsed >= options.max_seconds && epoch < options.epochs) {
      summary.termination = TrainingTermination::kTimeLimit;
      break;
    }
  }
  model.params = best_params;
  summary.wall_time_s = std::chrono::duration<double>(clock::now() - start).count();
  return summary;
}

#define TRACKASSOC_INSTANTIATE_TRAINING(S)                                                                   \
  template PairEvaluation evaluate_pairs<S>(const SiameseModel<S>&, const TrackSequences&,                   \
                                            const TrackSequences&, const PairSet&, double,                   \
                                            std::vector<double>*);                                           \
  template double siamese_minibatch_step<S>(SiameseModel<S>&, const TrackSequences&, const TrackSequences&,  \
                                            std::span<const int32_t>, std::span<const int32_t>,              \
                                            std::span<const uint8_t>, int, AdamState<S>&,                    \
                                            const AdamOptions&, SiameseStepWorkspace<S>&, double, uint64_t); \
  template void translate_pair<S>(const SiameseModel<S>&, SequenceBatch<S>&, int, double, double);           \
  template SiameseTrainingSummary train_siamese<S>(                                                          \
      SiameseModel<S>&, const TrackSequences&, const TrackSequences&, const PairSet&, const PairSet&,        \
      const SiameseTrainingOptions&, const std::function<void(const SiameseEpochReport&)>&);

TRACKASSOC_INSTANTIATE_TRAINING(float)
TRACKASSOC_INSTANTIATE_TRAINING(double)

}  // namespace trackassoc
