// Association of two radars' asynchronous tracks with the Siamese BiLSTM (seed 003, docs/design.md §4.7).
//
// 1. Embed every track once: N1 + N2 BiLSTM passes, in batches of `batch_tracks` across TBB.
// 2. Score all N1×N2 pairs with the cheap head on |e1 − e2| (kernels/learning/siamese.hpp).
// 3. Solve a 2-D LAP (kernels/assignment/lap.hpp) on c_ij = log(p_min) − log(p_ij) for p_ij ≥ p_min and
//    c_ij = +inf (forbidden) otherwise, where p_min is the probability threshold, with every track
//    allowed to stay unassigned at cost 0. Every allowed pair costs ≤ 0, so the LAP keeps as many
//    confident pairs as a one-to-one assignment allows and maximises Σ log p over them (independent
//    pair likelihoods); pairs below the threshold are never associated.
// The paper recomputes both branches for every pair (O(N1·N2) BiLSTM passes);
// score_pairs_recomputing does exactly that, for the benchmark and as a cross-check.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/learning/siamese.hpp"

namespace trackassoc {

struct SiameseAssociationOptions {
  double probability_threshold = 0.5;  // p_min ∈ (0, 1)
  int batch_tracks = 64;               // tracks per embedding batch (one TBB task)
  void validate() const;               // throws InputError naming the field
};

struct SiameseAssociationResult {
  std::vector<int32_t> left_to_right;  // per radar-1 track: its radar-2 track, or −1
  std::vector<float> probability;      // N1×N2, row-major
  int64_t pairs_scored = 0;
  double embed_seconds = 0.0, score_seconds = 0.0, assign_seconds = 0.0, wall_time_s = 0.0;
};

// Step 3 alone: the LAP with a probability threshold on an N1×N2 row-major probability matrix.
std::vector<int32_t> assign_by_probability(std::span<const float> probability, int32_t n1, int32_t n2,
                                           double probability_threshold);

// Embeddings (2H×N) of all tracks, in batches across TBB; deterministic.
MatrixX<float> embed_tracks(const SiameseModel<float>& model, const TrackSequences& tracks,
                            int batch_tracks = 64);

SiameseAssociationResult associate_siamese(const SiameseModel<float>& model, const TrackSequences& radar1,
                                           const TrackSequences& radar2,
                                           const SiameseAssociationOptions& options);

// A model of a concatenated-pair architecture (the LSTM / BiLSTM baselines) is scored this way
// in associate_siamese, since it has no per-track embedding.
// The paper's way: every pair through both branches again. prob is N1×N2, row-major.
void score_pairs_recomputing(const SiameseModel<float>& model, const TrackSequences& radar1,
                             const TrackSequences& radar2, std::span<float> prob);

// Correct association rate against truth: the share of radar-1 tracks whose decision (a radar-2
// track, or none) is right. A track whose target radar 2 does not see is right when unassigned.
double correct_association_rate(std::span<const int32_t> left_to_right, std::span<const int32_t> target1,
                                std::span<const int32_t> target2);

}  // namespace trackassoc
