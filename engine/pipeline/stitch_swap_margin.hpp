// The swap margin of fragment stitching's joins (docs/design.md §4.10; engine/pipeline/track_stitching.hpp).
//
// Stitching picks its joins by one assignment over the gated (end, start) pairs of positive
// evidence. Where traffic is dense, two targets that fade near one another and come back near one
// another offer two assignments of almost equal likelihood: the right one and the one that swaps
// their successors. The assignment takes the better of the two by whatever small margin there is,
// and a swap joins two long chains of two targets (on widearea, 260 output targets bridged by a
// join carried 14 600 of the 17 900 false key pairs). The margin of a join is how much better the
// chosen assignment is than the best alternative that differs from it by one exchange with a
// rival (a 2-opt move, as the "assignment margin" of the multi-target tracking literature weighs
// an assignment against its nearest competitor):
//   * its end a takes another gated start b' (cost c(a, b')), whose predecessor a' in the
//     assignment (if any) gives b' up and takes a's start b instead, or nothing when that is
//     cheaper or (a', b) is not a gated pair:
//       alt = c(a, b') + min(0, c(a', b)) − c(a', b'),    margin = alt − c(a, b);
//   * the mirror: its start b is taken by another gated end a'', whose successor b'' is given to a
//     or to nobody.
// The margin is +inf when the join has no rival. It is ≥ 0 when the assignment is optimal, and a
// negative log-likelihood-ratio difference: the odds of the chosen pairing over the swap are e^margin.
// A join is kept when its margin is at least `min_margin` (TrackStitchOptions::swap_margin). Both
// joins of an ambiguous swap then stay apart (two fragmented targets instead of two false ones).
// Measured on widearea (seed 1, `associate`, `evaluate`): min_margin 0 / 1 / 2 / 3 / 3.5 / 4 / 5
// gives fragment pairs 91.44 / 91.29 / 91.05 / 90.69 / 90.47 / 90.17 / 89.34 % and pair precision
// 99.25 / 99.37 / 99.44 / 99.49 / 99.53 / 99.53 / 99.57 %; a plain floor on every join's evidence
// instead buys less precision for the recall it costs (1 nat: 90.66 / 99.38 %, 2 nats: 89.41 / 99.48 %).
// Complexity: O(Σ over joins of (rivals of its end + rivals of its start) × the rivals of one end),
// the look-up of c(a', b) being a scan of a'`s candidates.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace trackassoc {

// The candidates that entered the assignment, sorted by end: end[i] → start[i] at cost[i] (< 0).
struct StitchCandidates {
  std::span<const int32_t> end, start;
  std::span<const double> cost;
};

// The swap margin of every join of `successor` (successor[a]: end a's start, −1 none; over
// `groups` groups), per end: +inf for an end without a join or a join without a rival. Throws
// std::invalid_argument on a join that is not among the candidates (a bug of the caller).
std::vector<double> stitch_swap_margins(int32_t groups, const StitchCandidates& candidates,
                                        std::span<const int32_t> successor);

}  // namespace trackassoc
