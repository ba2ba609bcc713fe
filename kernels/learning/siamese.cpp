// Siamese BiLSTM pair classifier (see siamese.hpp): batching, head, loss and gradient.
#include "kernels/learning/siamese.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {

void SiameseShape::validate() const {
  require(input == 3, "SiameseShape.input", "must be 3 (x, y, t), got " + std::to_string(input));
  require(hidden >= 1 && hidden <= 4096, "SiameseShape.hidden",
          "must be in [1, 4096], got " + std::to_string(hidden));
  require(fc >= 1 && fc <= 65536, "SiameseShape.fc", "must be in [1, 65536], got " + std::to_string(fc));
}

void TrackNormalisation::validate() const {
  require(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(t0), "TrackNormalisation",
          "x0, y0, t0 must be finite");
  require(std::isfinite(position_scale) && position_scale > 0, "TrackNormalisation.position_scale",
          "must be finite and > 0");
  require(std::isfinite(time_scale) && time_scale > 0, "TrackNormalisation.time_scale",
          "must be finite and > 0");
}

void TrackSequences::validate(const char* name) const {
  const std::string where(name);
  require(!offset.empty() && offset[0] == 0, where + ".offset", "must start with 0");
  require(x.size() == y.size() && x.size() == t.size(), where, "x, y, t must have equal lengths");
  require(
      static_cast<std::size_t>(offset.back()) == x.size(), where + ".offset",
      "last offset " + std::to_string(offset.back()) + " != number of points " + std::to_string(x.size()));
  for (std::size_t k = 0; k + 1 < offset.size(); ++k)
    require(offset[k + 1] > offset[k], where + ".offset", "track " + std::to_string(k) + " has no points");
  for (std::size_t i = 0; i < x.size(); ++i)
    require(std::isfinite(x[i]) && std::isfinite(y[i]) && std::isfinite(t[i]), where,
            "point " + std::to_string(i) + " is not finite");
  for (std::size_t k = 0; k + 1 < offset.size(); ++k)  // a track is a time-ordered sequence
    for (int64_t i = offset[k] + 1; i < offset[k + 1]; ++i)
      require(t[i] >= t[i - 1], where + ".t",
              "track " + std::to_string(k) + ": time goes backwards at point " + std::to_string(i));
}

template <class S>
void siamese_initialise(SiameseModel<S>& model, uint64_t seed) {
  model.shape.validate();
  const SiameseShape& sh = model.shape;
  model.params.assign(static_cast<std::size_t>(sh.parameter_count()), S(0));
  CounterRng rng(seed, 0, 3);
  const int H = sh.hidden;
  const double lstm_bound = 1.0 / std::sqrt(static_cast<double>(H));
  const int64_t per_dir = sh.lstm().parameter_count();
  for (int dir = 0; dir < sh.directions(); ++dir) {
    S* p = model.params.data() + dir * per_dir;
    for (int64_t k = 0; k < per_dir; ++k) p[k] = static_cast<S>(rng.uniform(-lstm_bound, lstm_bound));
    S* b = p + 4LL * H * sh.input + 4LL * H * H;
    for (int k = H; k < 2 * H; ++k) b[k] = S(1);  // forget-gate bias
  }
  S* head = model.params.data() + sh.branch_parameter_count();
  const double b1 = 1.0 / std::sqrt(static_cast<double>(sh.embedding()));
  for (int64_t k = 0; k < int64_t{sh.fc} * sh.embedding() + sh.fc; ++k)
    head[k] = static_cast<S>(rng.uniform(-b1, b1));
  const double b2 = 1.0 / std::sqrt(static_cast<double>(sh.fc));
  for (int64_t k = int64_t{sh.fc} * sh.embedding() + sh.fc; k < sh.head_parameter_count(); ++k)
    head[k] = static_cast<S>(rng.uniform(-b2, b2));
}

template <class S>
static SequenceBatch<S> make_batch_impl(const TrackSequences* const* sets,
                                        const std::span<const int32_t>* which, int nsets,
                                        const TrackNormalisation& norm) {
  int B = 0, T = 0;
  for (int s = 0; s < nsets; ++s) {
    B += static_cast<int>(which[s].size());
    for (int32_t k : which[s]) T = std::max(T, sets[s]->length(k));
  }
  SequenceBatch<S> batch;
  batch.steps.assign(T, MatrixX<S>::Zero(3, B));
  batch.mask = MatrixX<S>::Zero(T, B);
  const double inv_l = 1.0 / norm.position_scale, inv_t = 1.0 / norm.time_scale;
  int col = 0;
  for (int s = 0; s < nsets; ++s) {
    const TrackSequences& tr = *sets[s];
    for (int32_t k : which[s]) {
      const int64_t begin = tr.offset[k];
      const int len = tr.length(k);
      for (int i = 0; i < len; ++i) {
        batch.steps[i](0, col) = static_cast<S>((tr.x[begin + i] - norm.x0) * inv_l);
        batch.steps[i](1, col) = static_cast<S>((tr.y[begin + i] - norm.y0) * inv_l);
        batch.steps[i](2, col) = static_cast<S>((tr.t[begin + i] - norm.t0) * inv_t);
        batch.mask(i, col) = S(1);
      }
      ++col;
    }
  }
  return batch;
}

template <class S>
SequenceBatch<S> make_sequence_batch(const TrackSequences& tracks, std::span<const int32_t> which,
                                     const TrackNormalisation& norm) {
  const TrackSequences* sets[1] = {&tracks};
  return make_batch_impl<S>(sets, &which, 1, norm);
}

template <class S>
SequenceBatch<S> make_pair_batch(const TrackSequences& left_tracks, std::span<const int32_t> left,
                                 const TrackSequences& right_tracks, std::span<const int32_t> right,
                                 const TrackNormalisation& norm) {
  const TrackSequences* sets[2] = {&left_tracks, &right_tracks};
  const std::span<const int32_t> which[2] = {left, right};
  return make_batch_impl<S>(sets, which, 2, norm);
}

template <class S>
SequenceBatch<S> make_model_pair_batch(const SiameseModel<S>& model, const TrackSequences& lt,
                                       std::span<const int32_t> l, const TrackSequences& rt,
                                       std::span<const int32_t> r) {
  if (model.shape.architecture == PairArchitecture::kSiamese)
    return make_pair_batch<S>(lt, l, rt, r, model.normalisation);
  // One sequence per pair: the points of the left track, then those of the right track.
  const TrackNormalisation& norm = model.normalisation;
  const int B = static_cast<int>(l.size());
  int T = 0;
  for (int b = 0; b < B; ++b) T = std::max(T, lt.length(l[b]) + rt.length(r[b]));
  SequenceBatch<S> batch;
  batch.steps.assign(T, MatrixX<S>::Zero(3, B));
  batch.mask = MatrixX<S>::Zero(T, B);
  const double inv_l = 1.0 / norm.position_scale, inv_t = 1.0 / norm.time_scale;
  for (int b = 0; b < B; ++b) {
    int step = 0;
    for (const auto& [tr, k] : {std::pair<const TrackSequences*, int32_t>{&lt, l[b]}, {&rt, r[b]}}) {
      for (int64_t i = tr->offset[k]; i < tr->offset[k + 1]; ++i, ++step) {
        batch.steps[step](0, b) = static_cast<S>((tr->x[i] - norm.x0) * inv_l);
        batch.steps[step](1, b) = static_cast<S>((tr->y[i] - norm.y0) * inv_l);
        batch.steps[step](2, b) = static_cast<S>((tr->t[i] - norm.t0) * inv_t);
        batch.mask(step, b) = S(1);
      }
    }
  }
  return batch;
}

namespace {

// The recurrent branch: BiLSTM, or one forward LSTM for the concatenated-LSTM baseline.
template <class S>
void branch_forward(const SiameseModel<S>& m, const SequenceBatch<S>& x, MatrixX<S>& out,
                    BiLstmCache<S>* cache) {
  if (m.shape.directions() == 2)
    bilstm_forward(m.branch(), m.shape.lstm(), x, out, cache);
  else
    lstm_forward(m.branch(), m.shape.lstm(), x, false, out, cache ? &cache->forward : nullptr);
}

template <class S>
void branch_backward(const SiameseModel<S>& m, const SequenceBatch<S>& x, const BiLstmCache<S>& cache,
                     const MatrixX<S>& d_out, S* grad) {
  if (m.shape.directions() == 2)
    bilstm_backward(m.branch(), m.shape.lstm(), x, cache, d_out, grad);
  else
    lstm_backward(m.branch(), m.shape.lstm(), x, false, cache.forward, d_out, grad);
}

template <class S>
struct HeadViews {
  Eigen::Map<const MatrixX<S>> w1;
  Eigen::Map<const VectorX<S>> b1, w2;
  S b2;
  explicit HeadViews(const SiameseModel<S>& m)
      : w1(m.head(), m.shape.fc, m.shape.embedding()),
        b1(m.head() + int64_t{m.shape.fc} * m.shape.embedding(), m.shape.fc),
        w2(m.head() + int64_t{m.shape.fc} * m.shape.embedding() + m.shape.fc, m.shape.fc),
        b2(m.head()[m.shape.head_parameter_count() - 1]) {}
};

}  // namespace

template <class S>
void siamese_embed(const SiameseModel<S>& model, const SequenceBatch<S>& tracks, MatrixX<S>& embedding) {
  branch_forward(model, tracks, embedding, static_cast<BiLstmCache<S>*>(nullptr));
}

template <class S>
void siamese_head_logits(const SiameseModel<S>& model, const MatrixX<S>& d, VectorX<S>& logits) {
  const HeadViews<S> h(model);
  MatrixX<S> a = h.w1 * d;
  a.colwise() += h.b1;
  a = a.cwiseMax(S(0));
  logits = (h.w2.transpose() * a).transpose();
  logits.array() += h.b2;
}

template <class S>
void siamese_score_all_pairs(const SiameseModel<S>& model, const MatrixX<S>& e1, const MatrixX<S>& e2,
                             std::span<S> prob) {
  const Eigen::Index n1 = e1.cols(), n2 = e2.cols();
  constexpr std::size_t kRowsPerTask = 8;
  parallel_for_range(static_cast<std::size_t>(n1), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
    MatrixX<S> d(e1.rows(), n2);
    VectorX<S> z;
    for (std::size_t i = begin; i < end; ++i) {
      d = (e2.colwise() - e1.col(static_cast<Eigen::Index>(i))).cwiseAbs();
      siamese_head_logits(model, d, z);
      for (Eigen::Index j = 0; j < n2; ++j)
        prob[i * static_cast<std::size_t>(n2) + static_cast<std::size_t>(j)] =
            S(1) / (S(1) + std::exp(-z[j]));
    }
  });
}

template <class S>
void siamese_pair_logits(const SiameseModel<S>& model, const SequenceBatch<S>& pairs, VectorX<S>& logits) {
  MatrixX<S> e;
  branch_forward(model, pairs, e, static_cast<BiLstmCache<S>*>(nullptr));
  if (model.shape.architecture != PairArchitecture::kSiamese) {
    siamese_head_logits(model, e, logits);
    return;
  }
  const Eigen::Index b = e.cols() / 2;
  const MatrixX<S> d = (e.leftCols(b) - e.rightCols(b)).cwiseAbs();
  siamese_head_logits(model, d, logits);
}

double binary_cross_entropy_from_logit(double z, int label) {
  // softplus(z) − y·z = max(z, 0) − y·z + log(1 + e^{−|z|}).
  return std::max(z, 0.0) - label * z + std::log1p(std::exp(-std::abs(z)));
}

template <class S>
double siamese_loss_and_gradient(const SiameseModel<S>& model, const SequenceBatch<S>& pairs,
                                 std::span<const uint8_t> labels, S* grad,
                                 std::type_identity_t<VectorX<S>>* logits_out) {
  const SiameseShape& sh = model.shape;
  const bool siamese = sh.architecture == PairArchitecture::kSiamese;
  const int B = siamese ? pairs.batch() / 2 : pairs.batch();
  BiLstmCache<S> cache;
  MatrixX<S> e;
  branch_forward(model, pairs, e, &cache);
  // Head input: D = |e1 − e2| (Siamese) or the branch output itself (concatenated pair).
  const MatrixX<S> diff = siamese ? MatrixX<S>(e.leftCols(B) - e.rightCols(B)) : MatrixX<S>();
  const MatrixX<S> d = siamese ? MatrixX<S>(diff.cwiseAbs()) : e;
  const HeadViews<S> h(model);
  MatrixX<S> z1 = h.w1 * d;  // pre-activation, fc×B
  z1.colwise() += h.b1;
  const MatrixX<S> a = z1.cwiseMax(S(0));
  VectorX<S> z = (h.w2.transpose() * a).transpose();
  z.array() += h.b2;

  double loss = 0;
  MatrixX<S> dz(1, B);  // dL/dz = σ(z) − y (seed 003: binary cross-entropy)
  for (int b = 0; b < B; ++b) {
    loss += binary_cross_entropy_from_logit(static_cast<double>(z[b]), labels[b]);
    dz(0, b) = S(1) / (S(1) + std::exp(-z[b])) - static_cast<S>(labels[b]);
  }
  if (logits_out) *logits_out = z;

  S* gh = grad + sh.branch_parameter_count();
  Eigen::Map<MatrixX<S>> gw1(gh, sh.fc, sh.embedding());
  Eigen::Map<VectorX<S>> gb1(gh + int64_t{sh.fc} * sh.embedding(), sh.fc);
  Eigen::Map<VectorX<S>> gw2(gh + int64_t{sh.fc} * sh.embedding() + sh.fc, sh.fc);
  gw2.noalias() += a * dz.transpose();
  gh[sh.head_parameter_count() - 1] += dz.sum();
  MatrixX<S> dz1 = h.w2 * dz;  // fc×B
  dz1 = (z1.array() > S(0)).select(dz1, S(0));
  gw1.noalias() += dz1 * d.transpose();
  gb1.noalias() += dz1.rowwise().sum();
  const MatrixX<S> dd = h.w1.transpose() * dz1;  // 2H×B
  if (!siamese) {
    branch_backward(model, pairs, cache, dd, grad);
    return loss;
  }
  // d|u|/du = sign(u); the left branch gets +sign·dD, the right branch −sign·dD.
  MatrixX<S> de(sh.embedding(), 2 * B);
  const MatrixX<S> sgn = diff.unaryExpr([](S u) { return u > S(0) ? S(1) : (u < S(0) ? S(-1) : S(0)); });
  de.leftCols(B) = dd.cwiseProduct(sgn);
  de.rightCols(B) = -de.leftCols(B);
  branch_backward(model, pairs, cache, de, grad);
  return loss;
}

#define TRACKASSOC_INSTANTIATE_SIAMESE(S)                                                                \
  template void siamese_initialise<S>(SiameseModel<S>&, uint64_t);                                       \
  template SequenceBatch<S> make_sequence_batch<S>(const TrackSequences&, std::span<const int32_t>,      \
                                                   const TrackNormalisation&);                           \
  template SequenceBatch<S> make_pair_batch<S>(const TrackSequences&, std::span<const int32_t>,          \
                                               const TrackSequences&, std::span<const int32_t>,          \
                                               const TrackNormalisation&);                               \
  template SequenceBatch<S> make_model_pair_batch<S>(const SiameseModel<S>&, const TrackSequences&,      \
                                                     std::span<const int32_t>, const TrackSequences&,    \
                                                     std::span<const int32_t>);                          \
  template void siamese_embed<S>(const SiameseModel<S>&, const SequenceBatch<S>&, MatrixX<S>&);          \
  template void siamese_head_logits<S>(const SiameseModel<S>&, const MatrixX<S>&, VectorX<S>&);          \
  template void siamese_score_all_pairs<S>(const SiameseModel<S>&, const MatrixX<S>&, const MatrixX<S>&, \
                                           std::span<S>);                                                \
  template void siamese_pair_logits<S>(const SiameseModel<S>&, const SequenceBatch<S>&, VectorX<S>&);    \
  template double siamese_loss_and_gradient<S>(const SiameseModel<S>&, const SequenceBatch<S>&,          \
                                               std::span<const uint8_t>, S*,                             \
                                               std::type_identity_t<VectorX<S>>*);

TRACKASSOC_INSTANTIATE_SIAMESE(float)
TRACKASSOC_INSTANTIATE_SIAMESE(double)

}  // namespace trackassoc
