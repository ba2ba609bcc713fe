// The weight of a two-component mixture whose components are known, learnt from samples: fragment
// stitching's manoeuvre weight (docs/design.md §4.10; engine/pipeline/track_stitching.hpp), the
// mixing probability of two motion models as an IMM's mode probability is estimated from data.
//
// Model: p(x) = (1 − π) f₀(x) + π f₁(x) with f₀, f₁ fixed; each sample enters as d = ln f₁(x) −
// ln f₀(x). The estimate is the posterior mode of π under a Beta prior worth w pseudo-samples at π₀
// (Beta(w π₀ + 1, w (1 − π₀) + 1)), the maximum of
//     ℓ(π) = Σ_j ln(1 − π + π e^{d_j}) + w π₀ ln π + w (1 − π₀) ln(1 − π),
// whose fixed-point form is EM's (Dempster, Laird, Rubin, JRSS B 39(1) 1977; McLachlan & Peel,
// "Finite Mixture Models", 2000, §2.8): π = (Σ r_j + w π₀) / (J + w), r_j = π e^{d_j} / (1 − π + π e^{d_j})
// the responsibility of f₁. ℓ is concave, so its score ℓ'(π) = Σ (e^{d_j} − 1) / (1 − π + π e^{d_j})
// + w π₀ / π − w (1 − π₀) / (1 − π) decreases, and the root is found by bisection on [1e-6, 1 − 1e-6]
// (60 halvings: to 1e-18 of the interval), not by EM's fixed-point steps, which crawl when most
// samples say little (d ≈ 0) and stop early.
// Complexity: O(J) per halving, 60 halvings.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

namespace trackassoc {

// π̂ from the samples' log-ratios d = ln f₁ − ln f₀, under a Beta prior of `prior_weight`
// pseudo-samples at `prior`; `prior` itself when it is 0 or 1, when there are no samples, or when
// nothing (neither the samples nor the prior) tells π apart.
double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight);

// The same mixture when a sample's weight depends on its span s_j ≥ 0 (fragment stitching: the time
// its two predictions bridge):
//     π(s) = 1 − (1 − π_c) e^{−λ s},
// the second component being either present from the start (π_c: a new track's first velocities,
// whatever the gap) or begun during the span by a Poisson process of rate λ (a manoeuvre; an IMM's
// switching probability over an interval T follows from its mode's mean sojourn time 1/λ in the same
// way, Bar-Shalom, Li, Kirubarajan 2001 §11.6.7). (π_c, λ) maximise
//     ℓ = Σ_j ln(1 − π_j + π_j e^{d_j}) + (w/J) Σ_j [π₀ ln π_j + (1 − π₀) ln(1 − π_j)],
// the prior being w pseudo-samples at π₀ spread over the samples' spans: it alone is maximised by
// the constant π₀ (λ = 0), so a dependence on the span must come from the samples. When every span
// is the same the samples cannot tell π_c from λ: λ = 0 and π_c is mixture_weight's π̂. ℓ need not
// be concave, so it is searched on a grid (π_c: 20 values uniform in logit over [1e-6, 1 − 1e-6];
// λ s̄: 0 and 20 values log-uniform over [1e-3, 1e2], s̄ the mean span; the columns in parallel),
// π_c refined by golden section in the three best columns (ties to the lower rate, the answer the
// same for any number of threads), then λ by golden section between the best column's neighbours
// with π_c re-fitted at each. More than kMaxSamples samples are thinned by a stride ⌈J/kMaxSamples⌉,
// each kept one then weighing J / kept (widearea: 122 000 joins, every 25th). Complexity: O(1 000
// min(J, kMaxSamples)) evaluations of two logarithms: about 30-50 ms for 5 000 samples
// (test_mixture_weight).
struct SpanMixtureWeight {
  double constant = 0.0;  // π_c
  double rate = 0.0;      // λ [1 / unit of span]
  double mean_span = 0.0;
  double at(double span) const { return 1.0 - (1.0 - constant) * std::exp(-rate * span); }
};
inline constexpr std::size_t kMaxSamples = 5000;
// π_c = π₀ and λ = 0 when there are no samples or π₀ is 0 or 1. Throws std::invalid_argument
// unless there is one span (finite, ≥ 0) per log-ratio.
SpanMixtureWeight span_mixture_weight(std::span<const float> log_ratios, std::span<const float> spans,
                                      double prior, double prior_weight);

}  // namespace trackassoc
