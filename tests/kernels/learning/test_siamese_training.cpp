// Adam by hand, training on a tiny separable set, determinism for 1 vs 2 threads.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/learning/adam.hpp"
#include "kernels/learning/siamese_training.hpp"

using namespace trackassoc;

namespace {

// n targets on straight lines on a 4×4 grid of 20 km cells (well separated); each "radar" sees
// target k as track k with 200 m noise, radar 1 every 4 s from 0, radar 2 every 6 s from 1 s.
struct TinySet {
  TrackSequences left, right;
  PairSet pairs;
};

TinySet tiny_separable_set(int n, uint64_t seed) {
  TinySet s;
  CounterRng rng(seed);
  for (int k = 0; k < n; ++k) {
    const double x0 = 10000 + 20000 * (k % 4), y0 = 10000 + 20000 * (k / 4 % 4);
    const double heading = rng.uniform(0, 6.283185307179586), speed = rng.uniform(100, 200);
    auto add = [&](TrackSequences& tr, double period, double offset) {
      for (double t = offset; t <= 50; t += period) {
        tr.x.push_back(x0 + speed * std::cos(heading) * t + rng.normal(0, 200));
        tr.y.push_back(y0 + speed * std::sin(heading) * t + rng.normal(0, 200));
        tr.t.push_back(t);
      }
      tr.offset.push_back(static_cast<int64_t>(tr.x.size()));
    };
    add(s.left, 4, 0);
    add(s.right, 6, 1);
  }
  for (int k = 0; k < n; ++k) {
    s.pairs.left.push_back(k), s.pairs.right.push_back(k), s.pairs.label.push_back(1);
    s.pairs.left.push_back(k), s.pairs.right.push_back((k + 5) % n), s.pairs.label.push_back(0);
  }
  return s;
}

}  // namespace

TEST(Adam, FirstStepMovesEachParameterByTheLearningRate) {
  // After one step m̂ = g and v̂ = g², so Δθ = −α·g/(|g| + ε) ≈ −α·sign(g) (Kingma & Ba, §2.1).
  std::vector<double> p{1.0, -2.0, 3.0}, g{0.5, -4.0, 1e-3};
  AdamState<double> st;
  AdamOptions o;
  o.learning_rate = 0.1;
  o.clip_norm = 0;
  adam_step<double>(p, g, st, o);
  EXPECT_NEAR(p[0], 1.0 - 0.1 * 0.5 / (0.5 + 1e-8), 1e-12);
  EXPECT_NEAR(p[1], -2.0 + 0.1 * 4.0 / (4.0 + 1e-8), 1e-12);
  EXPECT_NEAR(p[2], 3.0 - 0.1 * 1e-3 / (1e-3 + 1e-8), 1e-12);
  EXPECT_EQ(st.step, 1);
}

TEST(Adam, DecoupledWeightDecayShrinksByLearningRateTimesLambda) {
  // AdamW (Loshchilov & Hutter 2019): the first step is −α·g/(|g| + ε) − α·λ·θ, worked out by hand;
  // a zero gradient leaves only the decay, θ·(1 − αλ).
  std::vector<double> p{2.0, -4.0}, g{0.5, 0.0};
  AdamState<double> st;
  AdamOptions o;
  o.learning_rate = 0.1;
  o.clip_norm = 0;
  o.weight_decay = 0.01;
  adam_step<double>(p, g, st, o);
  EXPECT_NEAR(p[0], 2.0 - 0.1 * 0.5 / (0.5 + 1e-8) - 0.1 * 0.01 * 2.0, 1e-12);
  EXPECT_NEAR(p[1], -4.0 * (1.0 - 0.1 * 0.01), 1e-12);
  o.weight_decay = -1.0;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(Adam, MinimisesAQuadratic) {
  std::vector<double> p{5.0, -3.0}, g(2);
  AdamState<double> st;
  AdamOptions o;
  o.learning_rate = 0.05;
  for (int k = 0; k < 2000; ++k) {
    g[0] = 2 * (p[0] - 1.0);
    g[1] = 20 * (p[1] + 2.0);
    adam_step<double>(p, g, st, o);
  }
  EXPECT_NEAR(p[0], 1.0, 1e-3);
  EXPECT_NEAR(p[1], -2.0, 1e-3);
}

TEST(Adam, ClipsTheGlobalNorm) {
  // With clipping the first step is still ±α (Adam is invariant to the gradient's scale), but the
  // reported norm is the unclipped one.
  std::vector<float> p{0.f, 0.f}, g{30.f, 40.f};
  AdamState<float> st;
  AdamOptions o;
  o.clip_norm = 1.0;
  EXPECT_NEAR(adam_step<float>(p, g, st, o), 50.0, 1e-9);
  EXPECT_NEAR(st.m[0], 0.1f * 0.6f, 1e-7f);  // (1−β1)·g·(1/50)
}

TEST(Adam, RejectsBadOptions) {
  AdamOptions o;
  o.beta1 = 1.0;
  EXPECT_THROW(o.validate(), InputError);
  try {
    o.validate();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beta1"), std::string::npos);
  }
}

TEST(SiameseTraining, TinySeparableSetReachesHundredPercent) {
  const TinySet s = tiny_separable_set(16, 3);
  SiameseModel<float> model;
  model.shape.hidden = 8;
  model.shape.fc = 16;
  SiameseTrainingOptions o;
  o.epochs = 300;
  o.batch_size = 8;
  o.chunk_pairs = 4;
  o.adam.learning_rate = 1e-2;
  o.learning_rate_decay = 1.0;
  o.patience = 300;
  const auto summary = train_siamese(model, s.left, s.right, s.pairs, s.pairs, o);
  const PairEvaluation ev = evaluate_pairs(model, s.left, s.right, s.pairs);
  EXPECT_EQ(ev.total(), 32);
  EXPECT_DOUBLE_EQ(ev.accuracy(), 1.0) << "after " << summary.epochs_run << " epochs, loss " << ev.mean_loss;
  EXPECT_LT(ev.mean_loss, 0.1);
  // The loss decreased from the first epoch.
  EXPECT_LT(summary.history.back().train_loss, summary.history.front().train_loss);
}

TEST(SiameseTraining, BitIdenticalForOneAndTwoThreads) {
  const TinySet s = tiny_separable_set(12, 4);
  auto run = [&](int threads, double shift) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    SiameseModel<float> model;
    model.shape.hidden = 6;
    model.shape.fc = 10;
    SiameseTrainingOptions o;
    o.augment_shift = shift;
    o.epochs = 3;
    o.batch_size = 12;
    o.chunk_pairs = 3;
    train_siamese(model, s.left, s.right, s.pairs, s.pairs, o);
    return model.params;
  };
  for (double shift : {0.0, 5000.0}) {
    const auto one = run(1, shift), two = run(2, shift);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t k = 0; k < one.size(); ++k) ASSERT_EQ(one[k], two[k]) << k << " shift " << shift;
  }
  // Augmentation changes the training (the test above is not comparing two identical no-ops).
  EXPECT_NE(run(1, 0.0), run(1, 5000.0));
}

TEST(SiameseTraining, TranslatePairMovesBothTracksOfAPairOnly) {
  const TinySet s = tiny_separable_set(4, 6);
  SiameseModel<float> model;
  model.normalisation.position_scale = 1000.0;
  const std::vector<int32_t> l{0, 1}, r{1, 2};
  auto batch = make_model_pair_batch<float>(model, s.left, l, s.right, r);
  const auto before = batch;
  translate_pair(model, batch, 1, 2000.0, -500.0);  // pair 1: columns 1 (left) and 3 (right)
  for (int t = 0; t < batch.length(); ++t)
    for (int c = 0; c < 4; ++c) {
      const bool moved = (c == 1 || c == 3) && before.mask(t, c) != 0.0f;
      EXPECT_FLOAT_EQ(batch.steps[t](0, c), before.steps[t](0, c) + (moved ? 2.0f : 0.0f));
      EXPECT_FLOAT_EQ(batch.steps[t](1, c), before.steps[t](1, c) + (moved ? -0.5f : 0.0f));
      EXPECT_EQ(batch.steps[t](2, c), before.steps[t](2, c));
    }
}

TEST(SiameseTraining, RejectsPairsOutOfRange) {
  TinySet s = tiny_separable_set(4, 5);
  s.pairs.right[2] = 99;
  SiameseModel<float> model;
  SiameseTrainingOptions o;
  try {
    train_siamese(model, s.left, s.right, s.pairs, s.pairs, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("training pairs.right"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
  }
}
