// The weight of a two-component mixture whose components are known, learnt from samples: fragment
// stitching's manoeuvre weight (docs/design.md §4.10; engine/pipeline/track_stitching.hpp), the
// mixing probability of two motion models as an IMM's mode probability is estimated from data.
//
// Algorithm: EM for π in p(x) = (1 − π) f₀(x) + π f₁(x) with f₀, f₁ fixed (Dempster, Laird, Rubin,
// JRSS B 39(1) 1977; McLachlan & Peel, "Finite Mixture Models", 2000, §2.8). Each sample enters as
// d = ln f₁(x) − ln f₀(x). E step: its responsibility r = π e^d / ((1 − π) + π e^d); M step: the
// posterior mode under a Beta prior worth w pseudo-samples at π₀, π = (Σ r + w π₀) / (J + w). The
// log-likelihood is concave in π, so the fixed point is the unique maximum; the iteration stops at
// a change below 1e-9 or after 200 steps, π kept in [1e-6, 1 − 1e-6].
// Complexity: O(J) per step.
#pragma once

#include <span>

namespace trackassoc {

// π̂ from the samples' log-ratios d = ln f₁ − ln f₀, under a Beta prior of `prior_weight`
// pseudo-samples at `prior`; `prior` itself when it is 0 or 1 or there are no samples.
double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight);

}  // namespace trackassoc
