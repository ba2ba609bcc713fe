// Siamese BiLSTM pair classifier for asynchronous tracks (seed 003, TTCSN, §2 and Algorithm 1).
//
// Model (seed 003 Algorithm 1):
//   e = BiLSTM(track), 2H-dimensional, shared by both branches         (Step 2, bilstm.hpp)
//   D = |e(x1) − e(x2)|, elementwise                                    (Step 3, §2.2 "L1 distance")
//   A = ReLU(W1·D + b1), fc units; z = w2ᵀ·A + b2; p = σ(z)             (Step 4, FC1 512 and FC2)
//   loss = binary cross-entropy,  −y·log p − (1−y)·log(1−p) = softplus(z) − y·z (computed from z).
// D is symmetric in (x1, x2), so p(x1, x2) = p(x2, x1) exactly (§2.3, tested).
//
// Input design (the paper gives only "points (x, y, t)" and "padding to the longest"): every point
// becomes the feature vector ((x − x0)/L, (y − y0)/L, (t − t0)/T) with a FIXED affine map stored with
// the model (TrackNormalisation), not per track or per pair: the embedding must keep absolute
// position and time, because two tracks are compared only through their embeddings, and a fixed map
// is what lets inference embed every track once. Defaults map the 100 × 100 km, 50 s seed 003 area
// to [−1, 1]² × [0, 1]. Padding is trailing and masked (bilstm.hpp), so it has no effect at all.
//
// Parameter layout (one flat vector): [BiLSTM forward | BiLSTM backward | W1 (fc×2H, column-major) |
// b1 (fc) | w2 (fc) | b2 (1)]. Initialisation as PyTorch: U(−1/√H, 1/√H) for the LSTM with the
// forget-gate bias set to 1 (Jozefowicz et al. 2015), U(−1/√fan_in, 1/√fan_in) for the dense layers.
//
// Complexity: embedding O(T·4H·(F+H)) per track; head O(fc·2H) per pair. Scoring all N1×N2 pairs by
// embedding each track once costs O((N1+N2)·T·4H·(F+H) + N1·N2·fc·2H); the paper recomputes both
// branches per pair, O(N1·N2·T·4H·(F+H)).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/core/enum_names.hpp"
#include "kernels/learning/bilstm.hpp"

namespace trackassoc {

// The pair classifiers of seed 003 §3: the Siamese network (TTCSN), and the two baselines that feed
// the concatenated pair to one recurrent network (§2.3: "h(x1 x2) ≠ h(x2 x1)"). For those, the pair is
// one sequence, the points of track 1 followed by the points of track 2 (time restarts where track 2
// begins), and the head reads the final state (LSTM: H; BiLSTM: [h_fwd(end); h_bwd(start)], 2H)
// instead of |e1 − e2|.
enum class PairArchitecture { kSiamese = 0, kConcatLstm = 1, kConcatBiLstm = 2 };
inline constexpr EnumName<PairArchitecture> kPairArchitectureNames[]{
    {PairArchitecture::kSiamese, "siamese"},
    {PairArchitecture::kConcatLstm, "lstm"},
    {PairArchitecture::kConcatBiLstm, "bilstm"}};
constexpr std::span<const EnumName<PairArchitecture>> enum_names(PairArchitecture) {
  return kPairArchitectureNames;
}

struct SiameseShape {
  int input = 3;    // features per point: x, y, t
  int hidden = 64;  // H per direction (seed 003: 64, embedding 128)
  int fc = 512;     // FC1 width (seed 003: 512)
  PairArchitecture architecture = PairArchitecture::kSiamese;
  LstmShape lstm() const { return {input, hidden}; }
  int directions() const { return architecture == PairArchitecture::kConcatLstm ? 1 : 2; }
  int embedding() const { return directions() * hidden; }  // branch output = head input size
  int64_t branch_parameter_count() const { return directions() * lstm().parameter_count(); }
  int64_t head_parameter_count() const { return int64_t{fc} * embedding() + 2LL * fc + 1; }
  int64_t parameter_count() const { return branch_parameter_count() + head_parameter_count(); }
  void validate() const;  // throws InputError naming the field
};

// Fixed affine input map (see the header comment). Stored with the weights.
struct TrackNormalisation {
  double x0 = 50000.0, y0 = 50000.0;  // [m] area centre
  double position_scale = 50000.0;    // L [m]
  double t0 = 0.0;                    // [s]
  double time_scale = 50.0;           // T [s]
  void validate() const;
};

// Ragged SoA set of tracks: track k is points [offset[k], offset[k+1]) of x, y, t (time-ordered).
// A track here is the sequence of converted plots (x, y, t) one radar reported for one target.
struct TrackSequences {
  std::vector<double> x, y, t;
  std::vector<int64_t> offset{0};
  int32_t size() const { return static_cast<int32_t>(offset.size()) - 1; }
  int32_t length(int32_t k) const { return static_cast<int32_t>(offset[k + 1] - offset[k]); }
  void validate(const char* name) const;  // non-empty tracks, finite values, sizes, times non-decreasing
};

// Pairs (left track of set 1, right track of set 2) with labels 1 = same target, 0 = different.
struct PairSet {
  std::vector<int32_t> left, right;
  std::vector<uint8_t> label;
  std::size_t size() const { return label.size(); }
};

template <class S>
struct SiameseModel {
  SiameseShape shape;
  TrackNormalisation normalisation;
  AlignedVector<S> params;  // shape.parameter_count()
  const S* branch() const { return params.data(); }
  const S* head() const { return params.data() + shape.branch_parameter_count(); }
};

// Sizes the parameter vector and draws the initial weights from CounterRng(seed, stream 3).
template <class S>
void siamese_initialise(SiameseModel<S>& model, uint64_t seed);

// Builds a padded, masked batch of the given tracks (columns in the order given).
template <class S>
SequenceBatch<S> make_sequence_batch(const TrackSequences& tracks, std::span<const int32_t> which,
                                     const TrackNormalisation& norm);

// Builds the batch of B pairs as 2B columns: left tracks first, then the right tracks, so both
// branches share one pass of the (shared-weight) BiLSTM.
template <class S>
SequenceBatch<S> make_pair_batch(const TrackSequences& left_tracks, std::span<const int32_t> left,
                                 const TrackSequences& right_tracks, std::span<const int32_t> right,
                                 const TrackNormalisation& norm);

// The batch a model's loss and logits expect for pairs (l[k], r[k]): make_pair_batch for the
// Siamese network, one concatenated sequence per pair otherwise.
template <class S>
SequenceBatch<S> make_model_pair_batch(const SiameseModel<S>& model, const TrackSequences& left_tracks,
                                       std::span<const int32_t> left, const TrackSequences& right_tracks,
                                       std::span<const int32_t> right);

// Embeddings of a batch of tracks: 2H×B (Siamese only).
template <class S>
void siamese_embed(const SiameseModel<S>& model, const SequenceBatch<S>& tracks, MatrixX<S>& embedding);

// The head on D = |e1 − e2| (2H×B): logits z, 1×B.
template <class S>
void siamese_head_logits(const SiameseModel<S>& model, const MatrixX<S>& d, VectorX<S>& logits);

// Probabilities of all N1×N2 pairs from the embeddings (2H×N1 and 2H×N2), row-major prob[i·N2 + j].
// Parallel over rows of 32 (TBB); deterministic.
template <class S>
void siamese_score_all_pairs(const SiameseModel<S>& model, const MatrixX<S>& e1, const MatrixX<S>& e2,
                             std::span<S> prob);

// Logits of the B pairs of a model pair batch (make_model_pair_batch).
template <class S>
void siamese_pair_logits(const SiameseModel<S>& model, const SequenceBatch<S>& pairs, VectorX<S>& logits);

// Summed binary cross-entropy of the B pairs of a model pair batch, and its gradient ADDED into `grad`
// (parameter_count() scalars). Writes the logits when `logits` is not null.
template <class S>
double siamese_loss_and_gradient(const SiameseModel<S>& model, const SequenceBatch<S>& pairs,
                                 std::span<const uint8_t> labels, S* grad,
                                 std::type_identity_t<VectorX<S>>* logits);

// Numerically stable BCE from a logit: softplus(z) − y·z.
double binary_cross_entropy_from_logit(double z, int label);

}  // namespace trackassoc
