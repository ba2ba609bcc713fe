// BiLSTM and Siamese head: analytic gradients against central finite differences (double),
// masking, symmetry.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "kernels/core/random.hpp"
#include "kernels/learning/bilstm.hpp"
#include "kernels/learning/siamese.hpp"

using namespace trackassoc;

namespace {

// Small random tracks (coordinates in metres / seconds, like the seed 003 area) with lengths 2..6.
TrackSequences random_tracks(int n, uint64_t seed, int min_len = 2, int max_len = 6) {
  TrackSequences tr;
  CounterRng rng(seed);
  for (int k = 0; k < n; ++k) {
    const int len = min_len + static_cast<int>(rng.uniform_int(max_len - min_len + 1));
    double x = rng.uniform(0, 100000), y = rng.uniform(0, 100000), t = rng.uniform(0, 5);
    const double vx = rng.uniform(-500, 500), vy = rng.uniform(-500, 500);
    for (int i = 0; i < len; ++i) {
      tr.x.push_back(x + vx * 4 * i + rng.normal(0, 300));
      tr.y.push_back(y + vy * 4 * i + rng.normal(0, 300));
      tr.t.push_back(t + 4 * i);
    }
    tr.offset.push_back(static_cast<int64_t>(tr.x.size()));
  }
  return tr;
}

SiameseModel<double> small_model(uint64_t seed, PairArchitecture arch = PairArchitecture::kSiamese) {
  SiameseModel<double> m;
  m.shape.architecture = arch;
  m.shape.hidden = 4;
  m.shape.fc = 6;
  siamese_initialise(m, seed);
  // Larger weights than the initialisation, so every gate and the ReLUs are exercised away from 0.
  CounterRng rng(seed, 7);
  for (auto& p : m.params) p += rng.normal(0, 0.3);
  return m;
}

// |a − b| / max(|a|, |b|), with the denominator floored at 1e-6 so that components that are exactly 0
// (a ReLU unit inactive on every pair) compare against the difference quotient's rounding (≈ 1e-12)
// without a spurious large ratio.
double relative_error(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-6});
}

}  // namespace

TEST(BiLstm, GradientMatchesCentralDifferences) {
  // L = Σ_b Σ_r w_rb · e_rb for fixed random w, so dL/de = w; check dL/dθ for every parameter.
  const LstmShape shape{3, 4};
  std::vector<double> params(2 * shape.parameter_count());
  CounterRng rng(11);
  for (auto& p : params) p = rng.normal(0, 0.5);
  const TrackSequences tr = random_tracks(5, 12);
  const std::vector<int32_t> which{0, 1, 2, 3, 4};
  const auto x = make_sequence_batch<double>(tr, which, TrackNormalisation{});
  ASSERT_GT(x.length(), 2);
  MatrixX<double> w(2 * shape.hidden, x.batch());
  for (Eigen::Index i = 0; i < w.size(); ++i) w.data()[i] = rng.normal();
  auto loss = [&](const std::vector<double>& p) {
    MatrixX<double> e;
    bilstm_forward(p.data(), shape, x, e, static_cast<BiLstmCache<double>*>(nullptr));
    return (e.array() * w.array()).sum();
  };
  BiLstmCache<double> cache;
  MatrixX<double> e;
  bilstm_forward(params.data(), shape, x, e, &cache);
  std::vector<double> grad(params.size(), 0.0);
  bilstm_backward(params.data(), shape, x, cache, w, grad.data());
  double worst = 0;
  const double h = 1e-6;
  for (std::size_t k = 0; k < params.size(); ++k) {
    auto p = params;
    p[k] = params[k] + h;
    const double up = loss(p);
    p[k] = params[k] - h;
    const double down = loss(p);
    const double numeric = (up - down) / (2 * h);
    worst = std::max(worst, relative_error(grad[k], numeric));
  }
  EXPECT_LT(worst, 1e-5);
}

class PairModelGradient : public ::testing::TestWithParam<PairArchitecture> {};

TEST_P(PairModelGradient, LossGradientMatchesCentralDifferences) {
  const SiameseModel<double> model = small_model(21, GetParam());
  const TrackSequences left = random_tracks(4, 22), right = random_tracks(4, 23);
  const std::vector<int32_t> li{0, 1, 2, 3}, ri{2, 0, 3, 1};
  const std::vector<uint8_t> labels{1, 0, 1, 0};
  const auto batch = make_model_pair_batch<double>(model, left, li, right, ri);
  std::vector<double> grad(model.params.size(), 0.0);
  siamese_loss_and_gradient(model, batch, labels, grad.data(), nullptr);
  std::vector<double> scratch(model.params.size());
  double worst = 0, worst_a = 0, worst_n = 0;
  std::size_t worst_k = 0;
  int checked = 0;
  // Fourth-order central difference, (−f(+2h) + 8f(+h) − 8f(−h) + f(−2h)) / 12h: truncation O(h⁴), so
  // h can be large enough that rounding (≈ 1e-16·|L|/h) stays far below 1e-5 of even the small
  // components of the gradient.
  const double h = 1e-4;
  auto m = model;
  for (std::size_t k = 0; k < model.params.size(); ++k) {
    auto at = [&](double delta) {
      m.params[k] = model.params[k] + delta;
      return siamese_loss_and_gradient(m, batch, labels, scratch.data(), nullptr);
    };
    const double f2 = at(2 * h), f1 = at(h), b1 = at(-h), b2 = at(-2 * h);
    m.params[k] = model.params[k];
    const double numeric = (-f2 + 8 * f1 - 8 * b1 + b2) / (12 * h);
    if (relative_error(grad[k], numeric) > worst) {
      worst = relative_error(grad[k], numeric);
      worst_k = k, worst_a = grad[k], worst_n = numeric;
    }
    ++checked;
  }
  EXPECT_EQ(checked, model.shape.parameter_count());
  EXPECT_LT(worst, 1e-5) << "parameter " << worst_k << ": analytic " << worst_a << ", numeric " << worst_n;
}

INSTANTIATE_TEST_SUITE_P(Architectures, PairModelGradient,
                         ::testing::Values(PairArchitecture::kSiamese, PairArchitecture::kConcatLstm,
                                           PairArchitecture::kConcatBiLstm),
                         [](const auto& info) { return std::string(enum_name(info.param)); });

TEST(Siamese, ConcatenatedPairBaselinesDependOnTheOrder) {
  // seed 003 §2.3: h(x1 x2) ≠ h(x2 x1) for the concatenated pair; the Siamese score is symmetric.
  for (auto arch : {PairArchitecture::kConcatLstm, PairArchitecture::kConcatBiLstm}) {
    const SiameseModel<double> model = small_model(61, arch);
    const TrackSequences a = random_tracks(3, 62), b = random_tracks(3, 63);
    const std::vector<int32_t> idx{0, 1, 2};
    VectorX<double> ab, ba;
    siamese_pair_logits(model, make_model_pair_batch<double>(model, a, idx, b, idx), ab);
    siamese_pair_logits(model, make_model_pair_batch<double>(model, b, idx, a, idx), ba);
    for (int i = 0; i < 3; ++i) EXPECT_GT(std::abs(ab[i] - ba[i]), 1e-9) << enum_name(arch) << " " << i;
    // The concatenated sequence is as long as both tracks.
    const auto batch = make_model_pair_batch<double>(model, a, idx, b, idx);
    EXPECT_EQ(batch.batch(), 3);
    EXPECT_EQ(batch.mask.col(0).sum(), a.length(0) + b.length(0));
  }
  EXPECT_EQ(small_model(1, PairArchitecture::kConcatLstm).shape.parameter_count(),
            4 * 4 * (3 + 4 + 1) + 6 * 4 + 6 + 6 + 1);
}

TEST(Siamese, BinaryCrossEntropyByHand) {
  // −log σ(2) = log(1 + e^−2); −log(1 − σ(2)) = log(1 + e^2).
  EXPECT_NEAR(binary_cross_entropy_from_logit(2.0, 1), std::log1p(std::exp(-2.0)), 1e-15);
  EXPECT_NEAR(binary_cross_entropy_from_logit(2.0, 0), std::log1p(std::exp(2.0)), 1e-14);
  EXPECT_NEAR(binary_cross_entropy_from_logit(-800.0, 1), 800.0, 1e-9);  // no overflow
}

TEST(Siamese, ScoreIsSymmetricInItsInputs) {
  const SiameseModel<double> model = small_model(31);
  const TrackSequences a = random_tracks(6, 32), b = random_tracks(6, 33);
  const std::vector<int32_t> idx{0, 1, 2, 3, 4, 5};
  VectorX<double> ab, ba;
  siamese_pair_logits(model, make_pair_batch<double>(a, idx, b, idx, model.normalisation), ab);
  siamese_pair_logits(model, make_pair_batch<double>(b, idx, a, idx, model.normalisation), ba);
  ASSERT_EQ(ab.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(ab[i], ba[i]) << i;  // bit-identical: |u| = |−u|
  // And the two pairs differ from each other (the test is not vacuous).
  EXPECT_NE(ab[0], ab[1]);
}

TEST(BiLstm, MaskingMakesPaddingIrrelevant) {
  // Embedding a track alone (no padding) equals embedding it in a batch padded to a longer track,
  // even with garbage in the padded slots.
  const LstmShape shape{3, 5};
  std::vector<float> params(2 * shape.parameter_count());
  CounterRng rng(41);
  for (auto& p : params) p = static_cast<float>(rng.normal(0, 0.5));
  const TrackSequences tr = random_tracks(2, 42, 2, 2);
  TrackSequences longer = random_tracks(1, 43, 9, 9);
  const std::vector<int32_t> zero{0};
  const auto alone = make_sequence_batch<float>(tr, zero, TrackNormalisation{});
  ASSERT_EQ(alone.length(), 2);
  // Batch: [short track, long track] padded to 9 steps; fill the padding with garbage.
  TrackSequences both = tr;
  both.x.resize(tr.offset[1]);
  both.y.resize(tr.offset[1]);
  both.t.resize(tr.offset[1]);
  both.offset.resize(2);
  for (std::size_t i = 0; i < longer.x.size(); ++i) {
    both.x.push_back(longer.x[i]);
    both.y.push_back(longer.y[i]);
    both.t.push_back(longer.t[i]);
  }
  both.offset.push_back(static_cast<int64_t>(both.x.size()));
  const std::vector<int32_t> pair{0, 1};
  auto padded = make_sequence_batch<float>(both, pair, TrackNormalisation{});
  ASSERT_EQ(padded.length(), 9);
  for (int t = 2; t < 9; ++t) {
    ASSERT_EQ(padded.mask(t, 0), 0.0f);
    padded.steps[t](0, 0) = 1e3f;
    padded.steps[t](1, 0) = -7.0f;
    padded.steps[t](2, 0) = 42.0f;
  }
  MatrixX<float> e_alone, e_padded;
  bilstm_forward(params.data(), shape, alone, e_alone, static_cast<BiLstmCache<float>*>(nullptr));
  bilstm_forward(params.data(), shape, padded, e_padded, static_cast<BiLstmCache<float>*>(nullptr));
  for (int r = 0; r < 2 * shape.hidden; ++r) EXPECT_EQ(e_alone(r, 0), e_padded(r, 0)) << r;

  // Gradients too: the padded batch's gradient for column 0 equals the unpadded one.
  BiLstmCache<float> ca, cp;
  bilstm_forward(params.data(), shape, alone, e_alone, &ca);
  bilstm_forward(params.data(), shape, padded, e_padded, &cp);
  MatrixX<float> d1 = MatrixX<float>::Ones(2 * shape.hidden, 1);
  MatrixX<float> d2 = MatrixX<float>::Zero(2 * shape.hidden, 2);
  d2.col(0).setOnes();
  std::vector<float> g1(params.size(), 0.f), g2(params.size(), 0.f);
  bilstm_backward(params.data(), shape, alone, ca, d1, g1.data());
  bilstm_backward(params.data(), shape, padded, cp, d2, g2.data());
  for (std::size_t k = 0; k < g1.size(); ++k) EXPECT_NEAR(g1[k], g2[k], 1e-6f * (1 + std::abs(g1[k]))) << k;
}

TEST(Siamese, EmbedOnceScoresEqualPerPairScores) {
  SiameseModel<double> model = small_model(51);
  const TrackSequences a = random_tracks(5, 52), b = random_tracks(7, 53);
  std::vector<int32_t> ia(5), ib(7);
  std::iota(ia.begin(), ia.end(), 0);
  std::iota(ib.begin(), ib.end(), 0);
  MatrixX<double> ea, eb;
  siamese_embed(model, make_sequence_batch<double>(a, ia, model.normalisation), ea);
  siamese_embed(model, make_sequence_batch<double>(b, ib, model.normalisation), eb);
  std::vector<double> prob(35);
  siamese_score_all_pairs<double>(model, ea, eb, prob);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 7; ++j) {
      const std::vector<int32_t> l{i}, r{j};
      VectorX<double> z;
      siamese_pair_logits(model, make_pair_batch<double>(a, l, b, r, model.normalisation), z);
      EXPECT_NEAR(prob[i * 7 + j], 1.0 / (1.0 + std::exp(-z[0])), 1e-12);
    }
}
