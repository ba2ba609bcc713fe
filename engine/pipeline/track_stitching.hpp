// Fragment stitching by track segment association (docs/design.md §4.10): one target followed by
// different sensors, or by one sensor's successive tracks, at different times. A target that leaves
// one radar's coverage and enters another's, or a track that a sensor drops and picks up later,
// gives output groups (the tuples of one target number) that never coexist; an association over
// common times can never link them, since they share no time. This pass, run on the default path
// after the association (and its registration), joins such groups as one assignment.
//
// Groups and candidates. A *group* is the set of local tracks of one target number of the record (a
// tuple of one member is a group too; a group with members on several sensors joins through any of
// them). Its end is its latest report x₀ (P₀) at t₀, its start time t₁ that of its earliest report.
// The start's state x₁ (P₁) is a *representative* report of the track that starts the group: a new
// track's first velocity comes from two plots (widearea: σ_v ≈ 100 m/s at the first report, 23 m/s
// at the fifth), so of its first start_reports reports the one whose estimate, predicted back to t₁
// with the quiet model, has the smallest ln det P (chosen from the covariances alone, never from a
// residual, so the choice does not bias the statistic) stands for the start.
// (G₁, G₂) is a candidate when G₂ starts within [t₀ − max_overlap_s, t₀ + max_gap_s], starts after
// G₁ starts and goes on after G₁ ends; so groups that coexist longer than max_overlap_s are not
// candidates (the association at common times has had its say on them), and every chain of joins
// runs forward in time (no cycles). One exception (transient_overlap): G₂ may start earlier when
// its representative (below) comes at or after t₀ − max_overlap_s and no sensor has a track in
// each group that overlap by more than max_overlap_s. The overlap then lies in G₂'s transient,
// where the association's statistic over the common times could not judge them: a handover with a
// short overlap whose new track's first velocities are those of two plots (recorded_recycled,
// recorded_covscale: docs/design.md §4.10).
//
// Gap statistic (track segment association: Yeom, Kirubarajan, Bar-Shalom, "Track segment
// association, fine-step IMM and initialization with Doppler for improved track performance", IEEE
// TAES 40(1) 2004, §II; Stone Soup's TrackStitcher, forward and backward prediction). G₁'s end is
// predicted forward and G₂'s start backward to the gap's midpoint t_m = (t₀ + t₁)/2 by constant
// velocity, x̂ = F(t_m − t) x, P̂ = F P Fᵀ + Q(|t_m − t|) (Q the continuous white-noise acceleration
// model of spectral density σ², Bar-Shalom, Li, Kirubarajan 2001 §6.2.2; backwards with F's
// direction), and compared with the sum of the predicted covariances:
//     e = x̂₁ − x̂₂,  S = P̂₁ + P̂₂,  m² = eᵀ S⁻¹ e.
// The statistic is symmetric in the two ends. (For this linear model it equals the forward-only
// m² of G₂'s start against G₁'s end predicted over the whole gap, since both residuals are one
// unit-determinant transform F(t₁ − t_m) of each other; engine/pipeline/track_hygiene.hpp's
// continuation_statistic.)
// A target may turn during the gap (recorded_recycled: gaps of 14-131 s with turns of up to 150°,
// and new tracks whose first velocity is off by 100s of m/s), which defeats a quiet CV model. So
// the join's likelihood is a two-model mixture, as the IMM of the reference: a quiet model
// (σ_a = manoeuvre_sigma, weight 1 − turn_probability) and a manoeuvring one (σ_a = turn_sigma,
// weight turn_probability),
//     p(e | same target) = (1 − π) N(e; 0, S_quiet) + π N(e; 0, S_turn),
// gated by m²_turn ≤ χ²_D(gate_probability). Chosen by measurement on the recorded family
// (docs/design.md §4.10): the mixture bridges the turns that the quiet gate refuses and keeps the
// quiet model's sharp likelihood for the pairs that did not manoeuvre, so a turning pair does not
// outbid a straight one.
// The turn weight is the file's own (learn_turn_probability): how often a target manoeuvres during
// a gap is a property of the scene (airliners on airways rarely, the recorded family's targets
// every 15-40 s), so it is learnt from the joins of a first assignment, as the weight of two known
// components (each join's responsibility r = π e^d / (1 − π + π e^d), d = ln N_turn − ln N_quiet),
// and as a function of the span s that the join's two predictions bridge:
//     π(s) = 1 − (1 − π_c) e^{−λ s},
// the manoeuvring model being needed either whatever the gap (π_c: a new track's first velocities,
// a lagging end) or because a manoeuvre began during it (a Poisson onset of rate λ, as an IMM's
// switching probability over an interval follows from its mode's sojourn time). (π̂_c, λ̂) is the
// posterior mode under a prior of turn_prior_joins = 10 pseudo-joins at turn_probability spread over
// the joins' spans (kernels/statistics/mixture_weight.hpp, span_mixture_weight), and the costs are
// re-weighed with π̂(s) before the final assignment (with the gap prior below). A small file keeps
// about the prior (recorded_recycled: 1-8 joins, π̂(s̄) 0.16-0.34), a large one speaks for itself
// (widearea: 122 000 joins, π̂_c ≈ 0.019 and λ̂ = 0; widearea_small: π̂(s̄) 0.059, a manoeuvre every
// 1 400 s). This replaced a rule that made a join outside the quiet gate only when neither side had
// another gated candidate and its evidence was ≥ 3 nats: that rule refused most turns where targets
// manoeuvre and cost precision where they do not (docs/design.md §4.10 has the measurements), and a
// weight that was the same at every gap (until session 28). The quiet model's σ_a is learnt with
// the weight (learn_quiet_sigma, engine/pipeline/stitch_join_cost.hpp: a grid from manoeuvre_sigma
// = 3 m/s² up, under a log-normal prior of median 6 m/s²), since no one value serves both scenes:
// 6 m/s² lifts recorded_recycled's correct rate 95.0 → 95.9 % and takes widearea's pair precision
// from 99.52 to 99.35 %, under issue 31's 99.5 % (docs/design.md §4.10). Ambiguity is the swap
// margin's (below).
//
// Assignment. Against "a different target" (any of the n group starts in G₁'s window [t₀ −
// max_overlap_s, t₀ + max_gap_s], each drawn from the density f of the groups' start states: the
// density n·f(x₁) of new starts, as in the track score of multiple-hypothesis tracking, Blackman &
// Popoli 1999 §6.2), the join's cost is the negative log-likelihood ratio
//     c₁₂ = −ln p(e | same target) + ln f(x₁) + ln n,
// f(x) = Π_i h_i(x_i), h_i the histogram of component i of the start states of the G − 1 *other*
// groups (B = ⌈√G⌉ bins of equal width over the range w_i ≥ 1 of all G, one count added to each:
// h_i = (c_k + 1) / ((G − 1 + B) w_i / B), c_k the others in x's bin; leave-one-out,
// kernels/statistics/histogram_density.hpp) (start_density_bins; without it f = 1 / V, V = Π w_i,
// the box of before). The box takes the
// starts' states as uniform, and a wide file's box is set by its wildest first velocities (widearea:
// |v| up to 3 400 m/s where targets fly at 150-280 m/s), so it made a start near a typical state
// look e⁴ times rarer than it is, and joins that cheap (the false pairs of widearea were 99 % false
// joins: docs/design.md §4.10).
// and one rectangular LAP over ends × starts (kernels/assignment/lap_sparse.hpp) with "no
// successor" and "no predecessor" at cost 0 picks the joins: only pairs of positive evidence
// (c < 0) can be made, and each group has at most one successor and one predecessor, globally
// optimal over the whole file (instead of per-pair rules). Joins are chained (G₁ → G₂ → G₃ is one
// target) and the later groups take the earliest group's target number. The tuples are unchanged;
// only `target` changes (filled when it was empty and a join was made).
// Swap margin (swap_margin). A join that an exchange with a rival nearly matches (two targets that
// fade near one another and come back near one another) is left unmade, so an ambiguous swap
// fragments two targets instead of joining each to the other's chain
// (engine/pipeline/stitch_swap_margin.hpp, with the measurements that chose 3.5 nats).
// Gap prior (gap_bin_s). The same target's gap follows its fades and re-initiations
// (widearea_small: 94 % of the true successors come within 120 s, in a window of 182 s), while a
// different target's start is uniform over the window W = max_overlap_s + max_gap_s; the join's
// likelihood ratio has the factor W·p(g), p the density of the same target's gaps. p is learnt
// from the file (empirical Bayes): the joins of a first assignment without the factor, binned by
// gap_bin_s with one count added to every bin (Laplace); then the assignment is solved again with
// c₁₂ − ln(W·p(g)). Few joins leave p near uniform (the recorded family's figures are unchanged);
// many learn the scene's gaps (widearea: false joins 2 943 → 2 073, correct 126 564 → 126 497).
// Candidates are searched through an index of the starts (engine/pipeline/stitch_index.hpp: a k-d
// tree over time and position with an exact bound of the pre-gate's reach), so an end looks only
// at the starts it could gate, not at every start of its window; the candidates, their order and
// the joins are those of the scan of the whole window with join_cost's own pre-gate, on each
// start's representative (the index holds the representatives, their window widened by the
// longest time from a start to its representative). Ends are searched in
// parallel.
// Complexity: O(G log G) to build, per end the index's nodes near its window and reach, O(D³) per
// start it returns, plus the sparse LAP's O(J·C log C) worst case for J joins of C candidates,
// solved twice (the first assignment, then with the learnt weight, σ_a and the gap prior), the
// weight's fit at each σ_a climbed (2 where the joins want the floor, at most 9; O(J·D³) each), and O(3·C·D³)
// to re-cost the candidates when σ_a moved; in practice the candidate graph is a sparse set of small chains.
// Memory: O(G) (the groups, the index, ~100 bytes a group; 16 row numbers a group while the
// representatives are chosen) plus the gated candidates (24 bytes each).
#pragma once

#include <cstdint>

#include "io/track_file.hpp"

namespace trackassoc {

struct TrackStitchOptions {
  bool enabled = true;
  double max_gap_s = 180.0;    // s, the longest gap bridged
  double max_overlap_s = 2.0;  // s, the overlap of a coasting end and its successor's start
  // σ_a [m/s²] of the quiet model: the first assignment's, and the least a file can learn.
  double manoeuvre_sigma = 3.0;
  double turn_sigma = 20.0;  // σ_a [m/s²] of the manoeuvring model
  // Its weight π in the mixture (0: the quiet model alone): the first assignment's and, when
  // learn_turn_probability, the prior's centre.
  double turn_probability = 0.2;
  double gate_probability = 0.9999;  // of χ²_D, on the manoeuvring model's m²
  // The turn model's weight π is learnt from the file's first joins (the header's empirical Bayes)
  // under a Beta prior of turn_prior_joins pseudo-joins at turn_probability (false: π as given).
  bool learn_turn_probability = true;
  double turn_prior_joins = 10.0;
  // With it, the quiet model's σ_a too (learn_quiet_sigma, engine/pipeline/stitch_join_cost.hpp): a
  // grid from manoeuvre_sigma up, under a log-normal prior of median quiet_sigma_prior and
  // log-standard deviation quiet_sigma_prior_sd (false: manoeuvre_sigma throughout).
  bool learn_quiet_sigma = true;
  double quiet_sigma_prior = 6.0;     // m/s²
  double quiet_sigma_prior_sd = 0.5;  // in ln σ_a
  // A join is made only when the assignment beats by at least this many nats every alternative that
  // exchanges it with a rival (engine/pipeline/stitch_swap_margin.hpp; 3.5: odds of e^3.5 ≈ 33 to 1;
  // 0: off).
  double swap_margin = 3.5;
  // The gap prior's histogram bin [s] (0: none; the gaps uniform over the window).
  double gap_bin_s = 20.0;
  // The start-state density f of "a different target": a histogram per state component (true), or
  // uniform over the box of the start states (false).
  bool start_density_bins = true;
  // The start's representative is chosen among its track's first start_reports reports (1: the
  // first report).
  int start_reports = 16;
  // A start may overlap the end by more than max_overlap_s when its representative report comes
  // after the end (less max_overlap_s), the groups hold no two overlapping tracks of one sensor and
  // the overlap is thus the new track's transient, which the association's statistic over common
  // times could not judge (a handover of one target with a short overlap).
  bool transient_overlap = true;
  void validate() const;
};

struct TrackStitchSummary {
  int32_t groups = 0, candidates = 0, stitches = 0;  // groups, gated pairs, and joins made
  // π̂(s̄) learnt from the first joins, at their mean span (0: not learnt), and the mean time
  // between manoeuvre onsets 1/λ̂ (0: none learnt, the weight the same at every span).
  double turn_probability = 0.0, manoeuvre_interval_s = 0.0;
  double quiet_sigma = 0.0;  // the quiet model's σ_a learnt with it [m/s²] (0: not learnt)
};

// The join's cost (the gap statistic and the mixture above) is engine/pipeline/stitch_join_cost.hpp's.
// Joins the groups of `record` (its tuple columns are file.sensors, in order) as above; `file`
// gives the reports (the registered reports where registration applies).
TrackStitchSummary stitch_fragments(const TrackFile& file, AssociationRecord& record,
                                    const TrackStitchOptions& options);

}  // namespace trackassoc
