// The weight of a two-component mixture with known components (kernels/statistics/mixture_weight.hpp):
// by hand where the responsibilities are 0 or 1 or the score has a closed-form root, and an injected
// weight recovered from samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
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

}  // namespace
}  // namespace trackassoc
