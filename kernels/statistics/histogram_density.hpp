// A histogram density estimate of one variable, evaluated at each sample with that sample left out:
// fragment stitching's density f of "a different target's start" (docs/design.md §4.10;
// engine/pipeline/track_stitching.hpp), where each start is scored against the density of the
// *other* starts.
//
// G samples x_g; B = ⌈√G⌉ bins of equal width w/B over [lo, lo + w], lo the smallest sample and w =
// max(range, 1) (the square-root choice of bin count, Scott, "Multivariate Density Estimation", 2nd
// ed. 2015, §3.2); one count added to each bin (Laplace). At sample g, the histogram of the others:
//     h^{(−g)}(x_g) = (c_k − 1 + 1) / ((G − 1 + B) w / B),   k the bin of x_g, c_k its count of all G,
// the leave-one-out estimate (Silverman, "Density Estimation for Statistics and Data Analysis",
// 1986, §3.4.3). Counting x_g in its own bin biases the density at x_g upwards by about one count
// in c_k, most where the samples are few (a file of 60 starts, 8 bins: ~13 % a component).
// Complexity O(G); memory O(B).
#pragma once

#include <span>
#include <vector>

namespace trackassoc {

// ln h^{(−g)}(x_g) for every sample g, in order; empty for no samples. Samples must be finite.
std::vector<double> leave_one_out_log_density(std::span<const double> samples);

}  // namespace trackassoc
