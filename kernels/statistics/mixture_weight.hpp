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

#include <span>

namespace trackassoc {

// π̂ from the samples' log-ratios d = ln f₁ − ln f₀, under a Beta prior of `prior_weight`
// pseudo-samples at `prior`; `prior` itself when it is 0 or 1, when there are no samples, or when
// nothing (neither the samples nor the prior) tells π apart.
double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight);

}  // namespace trackassoc
