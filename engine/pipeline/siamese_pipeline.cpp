// Siamese association pipeline (see siamese_pipeline.hpp).
#include "engine/pipeline/siamese_pipeline.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

void SiameseAssociationOptions::validate() const {
  require(probability_threshold > 0 && probability_threshold < 1,
          "SiameseAssociationOptions.probability_threshold",
          "must be in (0, 1), got " + std::to_string(probability_threshold));
  require(batch_tracks >= 1, "SiameseAssociationOptions.batch_tracks", "must be >= 1");
}

MatrixX<float> embed_tracks(const SiameseModel<float>& model, const TrackSequences& tracks,
                            int batch_tracks) {
  require(model.shape.architecture == PairArchitecture::kSiamese, "model",
          "only a Siamese model embeds single tracks; this one is " +
              std::string(enum_name(model.shape.architecture)));
  const std::size_t n = static_cast<std::size_t>(tracks.size());
  MatrixX<float> e(model.shape.embedding(), static_cast<Eigen::Index>(n));
  const std::size_t b = static_cast<std::size_t>(std::max(1, batch_tracks));
  const std::size_t batches = (n + b - 1) / b;
  parallel_for_range(batches, 1, [&](std::size_t bb, std::size_t be) {
    std::vector<int32_t> which;
    MatrixX<float> part;
    for (std::size_t k = bb; k < be; ++k) {
      which.resize(std::min(n, (k + 1) * b) - k * b);
      std::iota(which.begin(), which.end(), static_cast<int32_t>(k * b));
      siamese_embed(model, make_sequence_batch<float>(tracks, which, model.normalisation), part);
      e.middleCols(static_cast<Eigen::Index>(k * b), part.cols()) = part;
    }
  });
  return e;
}

std::vector<int32_t> assign_by_probability(std::span<const float> probability, int32_t n1, int32_t n2,
                                           double probability_threshold) {
  require(probability_threshold > 0 && probability_threshold < 1, "probability_threshold",
          "must be in (0, 1)");
  require(probability.size() == static_cast<std::size_t>(n1) * static_cast<std::size_t>(n2), "probability",
          "size must be n1·n2");
  std::vector<int32_t> left_to_right(static_cast<std::size_t>(n1), -1);
  if (n1 == 0 || n2 == 0) return left_to_right;
  const double log_min = std::log(probability_threshold);
  std::vector<double> cost(probability.size());
  bool any = false;
  for (std::size_t k = 0; k < cost.size(); ++k) {
    const double p = probability[k];
    require(p >= 0 && p <= 1, "probability", "entry " + std::to_string(k) + " is not in [0, 1]");
    const bool allowed = p >= probability_threshold;
    any = any || allowed;
    cost[k] = allowed ? log_min - std::log(p) : std::numeric_limits<double>::infinity();
  }
  if (!any) return left_to_right;
  LapOptions lo;
  lo.allow_unassigned = true;
  lo.unassigned_cost = 0.0;
  const LapResult lap = solve_lap(cost, n1, n2, lo);
  for (int32_t i = 0; i < n1; ++i) {
    const int32_t j = lap.row_to_col[i];
    if (j >= 0 && std::isfinite(cost[static_cast<std::size_t>(i) * n2 + j])) left_to_right[i] = j;
  }
  return left_to_right;
}

SiameseAssociationResult associate_siamese(const SiameseModel<float>& model, const TrackSequences& radar1,
                                           const TrackSequences& radar2,
                                           const SiameseAssociationOptions& options) {
  using clock = std::chrono::steady_clock;
  options.validate();
  radar1.validate("radar 1 tracks");
  radar2.validate("radar 2 tracks");
  const auto t0 = clock::now();
  SiameseAssociationResult r;
  const int32_t n1 = radar1.size(), n2 = radar2.size();
  r.probability.resize(static_cast<std::size_t>(n1) * n2);
  auto t1 = t0;
  if (model.shape.architecture == PairArchitecture::kSiamese) {
    const MatrixX<float> e1 = embed_tracks(model, radar1, options.batch_tracks);
    const MatrixX<float> e2 = embed_tracks(model, radar2, options.batch_tracks);
    t1 = clock::now();
    siamese_score_all_pairs<float>(model, e1, e2, r.probability);
  } else {  // the concatenated-pair baselines see both tracks at once: one pass per pair
    score_pairs_recomputing(model, radar1, radar2, r.probability);
  }
  r.pairs_scored = int64_t{n1} * n2;
  const auto t2 = clock::now();
  r.left_to_right = assign_by_probability(r.probability, n1, n2, options.probability_threshold);
  const auto t3 = clock::now();
  r.embed_seconds = std::chrono::duration<double>(t1 - t0).count();
  r.score_seconds = std::chrono::duration<double>(t2 - t1).count();
  r.assign_seconds = std::chrono::duration<double>(t3 - t2).count();
  r.wall_time_s = std::chrono::duration<double>(t3 - t0).count();
  return r;
}

void score_pairs_recomputing(const SiameseModel<float>& model, const TrackSequences& radar1,
                             const TrackSequences& radar2, std::span<float> prob) {
  const int32_t n1 = radar1.size(), n2 = radar2.size();
  parallel_for_range(static_cast<std::size_t>(n1), 1, [&](std::size_t b, std::size_t e) {
    VectorX<float> z;
    for (std::size_t i = b; i < e; ++i)
      for (int32_t j = 0; j < n2; ++j) {
        const int32_t l[1] = {static_cast<int32_t>(i)}, rr[1] = {j};
        siamese_pair_logits(model, make_model_pair_batch<float>(model, radar1, l, radar2, rr), z);
        prob[i * n2 + j] = 1.0f / (1.0f + std::exp(-z[0]));
      }
  });
}

double correct_association_rate(std::span<const int32_t> left_to_right, std::span<const int32_t> target1,
                                std::span<const int32_t> target2) {
  if (left_to_right.empty()) return 1.0;
  std::unordered_map<int32_t, int32_t> seen_by_2;
  for (std::size_t j = 0; j < target2.size(); ++j) seen_by_2[target2[j]] = static_cast<int32_t>(j);
  std::size_t correct = 0;
  for (std::size_t i = 0; i < left_to_right.size(); ++i) {
    const int32_t j = left_to_right[i];
    const bool exists = seen_by_2.count(target1[i]) > 0;
    if (j < 0 ? !exists : target2[j] == target1[i]) ++correct;
  }
  return double(correct) / double(left_to_right.size());
}

}  // namespace trackassoc
