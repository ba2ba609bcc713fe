// The weight of a two-component mixture with known components (kernels/statistics/mixture_weight.hpp):
// by hand where the responsibilities are 0 or 1 or the score has a closed-form root, and an injected
// weight recovered from samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "kernels/statistics/mixture_weight.hpp"

namespace trackassoc {
namespace {

TEST(MixtureWeight, SamplesThatEachComponentSurelyExplainsCountAsWholeSamples) {
  // d = ±100: each responsibility is 1 (or 0) to e^−90, so π̂ = (Σ r + w π₀) / (J + w) by hand.
  const std::vector<float> first(5, -100.0f), second(5, 100.0f);
  EXPECT_NEAR(mixture_weight(second, 0.2, 10.0), (5.0 + 2.0) / 15.0, 1e-9);
  EXPECT_NEAR(mixture_weight(first, 0.2, 10.0), 2.0 / 15.0, 1e-9);
  std::vector<float> both(first);
  both.insert(both.end(), second.begin(), second.end());
  EXPECT_NEAR(mixture_weight(both, 0.2, 0.0), 0.5, 1e-9);  // no prior: the share of the samples
  // Samples that say nothing (d = 0, the components alike) leave the prior where it is.
  const std::vector<float> alike(10, 0.0f);
  EXPECT_NEAR(mixture_weight(alike, 0.2, 10.0), 0.2, 1e-9);
  // Many samples that say nothing beside a few that say f₀: the score −1000/(1 − π) + 2/π − 8/(1 − π)
  // (1 000 at d = −50, 100 000 at d = 0, the prior 10 at 0.2) vanishes at π = 2/1010. EM's
  // fixed-point steps crawl here (the samples at d = 0 hold π where it is) and stopped at 0.0285.
  std::vector<float> mostly_alike(1000, -50.0f);
  mostly_alike.insert(mostly_alike.end(), 100000, 0.0f);
  EXPECT_NEAR(mixture_weight(mostly_alike, 0.2, 10.0), 2.0 / 1010.0, 1e-9);
  // No samples, or a weight of 0 or 1: the prior itself.
  EXPECT_EQ(mixture_weight({}, 0.2, 10.0), 0.2);
  EXPECT_EQ(mixture_weight(second, 0.0, 10.0), 0.0);
  EXPECT_EQ(mixture_weight(second, 1.0, 10.0), 1.0);
}

TEST(MixtureWeight, AnInjectedWeightIsRecovered) {
  // x drawn from (1 − π) N(0, 1) + π N(0, 5²) with π = 0.3; d = ln N(x; 0, 25) − ln N(x; 0, 1).
  // The estimate over 20 000 samples is within 0.015 of π (its standard error, √(π(1 − π)/J) ≈
  // 0.0032 inflated by the components' overlap, is below 0.005), from either side of the answer.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::bernoulli_distribution wide(0.3);
  std::vector<float> d;
  for (int j = 0; j < 20000; ++j) {
    const double x = (wide(rng) ? 5.0 : 1.0) * unit(rng);
    d.push_back(static_cast<float>((-0.5 * x * x / 25.0 - std::log(5.0)) - (-0.5 * x * x)));
  }
  EXPECT_NEAR(mixture_weight(d, 0.2, 10.0), 0.3, 0.015);
  EXPECT_NEAR(mixture_weight(d, 0.9, 0.0), 0.3, 0.015);
  // The prior's pull fades with the samples: 10 pseudo-samples at 0.05 move it by < 0.001.
  EXPECT_NEAR(mixture_weight(d, 0.05, 10.0), mixture_weight(d, 0.9, 0.0), 1e-3);
}

// span_mixture_weight: π(s) = 1 − (1 − π_c) e^{−λ s}.

// Samples of the span model: span s uniform on [0, 150], the second component with probability
// π(s); x drawn from it as above (N(0, 1) or N(0, 5²)) and d = ln N(x; 0, 25) − ln N(x; 0, 1).
void draw_span_samples(double constant, double rate, int n, std::vector<float>& d,
                       std::vector<float>& spans) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> span(0.0, 150.0);
  for (int j = 0; j < n; ++j) {
    const double s = span(rng);
    std::bernoulli_distribution wide(1.0 - (1.0 - constant) * std::exp(-rate * s));
    const double x = (wide(rng) ? 5.0 : 1.0) * unit(rng);
    d.push_back(static_cast<float>((-0.5 * x * x / 25.0 - std::log(5.0)) - (-0.5 * x * x)));
    spans.push_back(static_cast<float>(s));
  }
}

TEST(SpanMixtureWeight, EqualSpansGiveMixtureWeightsEstimate) {
  // With one span only π(s̄) is determined, and it maximises mixture_weight's ℓ: the same π̂.
  std::vector<float> d, spans;
  draw_span_samples(0.3, 0.0, 5000, d, spans);
  const std::vector<float> equal(d.size(), 60.0f);
  for (double prior : {0.2, 0.6}) {
    const SpanMixtureWeight w = span_mixture_weight(d, equal, prior, 10.0);
    EXPECT_NEAR(w.mean_span, 60.0, 1e-9);
    EXPECT_EQ(w.rate, 0.0);  // nothing to tell π_c from λ: the constant
    EXPECT_NEAR(w.at(60.0), mixture_weight(d, prior, 10.0), 1e-12);
    EXPECT_NEAR(w.at(0.0), w.at(150.0), 1e-12);
  }
  // The hand case of mixture_weight: 5 samples that the second component surely explains and a
  // prior of 10 at 0.2, π̂ = 7/15, whatever the (equal) span.
  const std::vector<float> second(5, 100.0f), spans5(5, 30.0f);
  const SpanMixtureWeight w = span_mixture_weight(second, spans5, 0.2, 10.0);
  EXPECT_NEAR(w.at(30.0), 7.0 / 15.0, 1e-6);
}

TEST(SpanMixtureWeight, AnInjectedConstantAndOnsetRateAreRecovered) {
  // π_c = 0.05 and λ = 1/50 s: π(0) = 0.05, π(150 s) = 0.953. 20 000 samples (thinned to 5 000,
  // each weighing 4) pin both.
  std::vector<float> d, spans;
  draw_span_samples(0.05, 1.0 / 50.0, 20000, d, spans);
  const SpanMixtureWeight w = span_mixture_weight(d, spans, 0.2, 10.0);
  EXPECT_NEAR(w.constant, 0.05, 0.02);
  EXPECT_NEAR(1.0 / w.rate, 50.0, 7.5);
  // A weight that does not grow with the span (λ = 0, π = 0.1): the fitted π(s) stays flat.
  std::vector<float> d0, spans0;
  draw_span_samples(0.1, 0.0, 20000, d0, spans0);
  const SpanMixtureWeight flat = span_mixture_weight(d0, spans0, 0.2, 10.0);
  EXPECT_NEAR(flat.constant, 0.1, 0.015);
  EXPECT_LT(flat.at(150.0) - flat.at(0.0), 0.02);
}

TEST(SpanMixtureWeight, ManySamplesAreThinnedAndStillRecoverTheInjectedModel) {
  // 100 000 samples (20 times kMaxSamples): every 20th is used, weighing 20.
  std::vector<float> d, spans;
  draw_span_samples(0.05, 1.0 / 50.0, 100000, d, spans);
  ASSERT_GT(d.size(), 4 * kMaxSamples);
  const SpanMixtureWeight w = span_mixture_weight(d, spans, 0.2, 10.0);
  EXPECT_NEAR(w.constant, 0.05, 0.02);
  EXPECT_NEAR(1.0 / w.rate, 50.0, 7.5);
}

TEST(SpanMixtureWeight, OneJoinSaysNothingOfTheSpan) {
  // One quiet sample (d = −3 at 30 s): π(s) is determined at 30 s only, so the answer is the
  // constant of mixture_weight (the root of its score, between the prior 0.2 and 0), not a rate
  // that the search happened to pick on the ridge of equal ℓ.
  const std::vector<float> d{-3.0f}, spans{30.0f};
  const SpanMixtureWeight w = span_mixture_weight(d, spans, 0.2, 10.0);
  EXPECT_EQ(w.rate, 0.0);
  EXPECT_NEAR(w.constant, mixture_weight(d, 0.2, 10.0), 1e-12);
  EXPECT_LT(w.constant, 0.2);
  // Two quiet samples at different spans: the prior, spread over both spans, favours the constant
  // π₀, and the samples pull both points down alike: π(100 s) stays within 0.05 of π(10 s).
  const std::vector<float> d2{-3.0f, -3.0f}, spans2{10.0f, 100.0f};
  const SpanMixtureWeight w2 = span_mixture_weight(d2, spans2, 0.2, 10.0);
  EXPECT_LT(w2.at(100.0) - w2.at(10.0), 0.05);
}

TEST(SpanMixtureWeight, NoSamplesOrADegeneratePriorOrBadSpans) {
  EXPECT_EQ(span_mixture_weight({}, {}, 0.2, 10.0).constant, 0.2);
  EXPECT_EQ(span_mixture_weight({}, {}, 0.2, 10.0).rate, 0.0);
  const std::vector<float> d{1.0f, -1.0f}, spans{10.0f, 20.0f}, one{10.0f}, negative{10.0f, -1.0f};
  EXPECT_EQ(span_mixture_weight(d, spans, 0.0, 10.0).constant, 0.0);
  EXPECT_THROW(span_mixture_weight(d, one, 0.2, 10.0), std::invalid_argument);
  EXPECT_THROW(span_mixture_weight(d, negative, 0.2, 10.0), std::invalid_argument);
}

}  // namespace
}  // namespace trackassoc
