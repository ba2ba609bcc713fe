// The cost of joining two fragments in fragment stitching (engine/pipeline/track_stitching.hpp has
// the rule, its references and its measurements): the gap statistic of one motion model (G₁'s end
// predicted forward and G₂'s start backward to the gap's midpoint, by constant velocity with the
// continuous white-noise acceleration Q of Bar-Shalom, Li, Kirubarajan 2001 §6.2.2), its diagonal
// pre-gate, and the two-model mixture's −ln p(e | same target). O(D³) per pair, no heap allocation
// (fixed-capacity Eigen matrices, D ≤ 6).
#pragma once

#include <cstddef>
#include <span>

#include "engine/pipeline/track_stitching.hpp"
#include "io/track_file.hpp"
#include "kernels/statistics/mixture_weight.hpp"

namespace trackassoc {

// The gap statistic of engine/pipeline/track_stitching.hpp's rule for one model: G₁'s end (row `end`)
// predicted forward and G₂'s start (row `start`) backward to their midpoint with q = σ_a², m² and ln det(2π
// S).
struct GapStatistic {
  double m2 = 0.0, log_det = 0.0;
  double log_density() const { return -0.5 * (m2 + log_det); }  // ln N(e; 0, S)
};
GapStatistic gap_statistic(const TrackTable& tracks, std::size_t end, std::size_t start, double q);

// The pre-gate of join_cost: true only when m² under q = σ_a² is surely above `gate`, from the
// diagonal alone (|e_p|² > gate·tr(S_pp) of the position part e_p, S_pp); the index of
// engine/pipeline/stitch_index.hpp bounds the pairs it keeps.
bool gap_surely_outside(const TrackTable& tracks, std::size_t end, std::size_t start, double q, double gate);

// The join's cost c₁₂ + ln V of engine/pipeline/track_stitching.hpp's rule (the mixture's −ln p(e | same
// target)), or +inf when the manoeuvring model's m² is outside the gate `gate` (χ²_D of gate_probability).
// `turn_log_ratio`, when given, receives ln N(e; 0, S_turn) − ln N(e; 0, S_quiet).
double join_cost(const TrackTable& tracks, std::size_t end, std::size_t start,
                 const TrackStitchOptions& options, double gate, double* turn_log_ratio = nullptr);

// The change of a join's cost when the second assignment revises the mixture (track_stitching.hpp,
// docs/design.md §4.10), for a gated pair (join_cost finite) and a weight in (0, 1):
// join_cost at (manoeuvre_sigma, turn_probability) + the change = join_cost at (sigma, turn_weight)
// (the quiet model's σ_a and the turn weight learnt, learn_quiet_sigma and span_mixture_weight).
// `turn_log_ratio` holds join_cost's ratio at manoeuvre_sigma (kept in float by the candidates)
// and gets the ratio at `sigma`. When σ_a is unchanged, only the weights change: the change is
// then computed from the ratio alone, with no gap statistic (exact but for the ratio's float).
// Constructed once for the file's σ_a (the logarithms of the first weight computed there), then
// applied to every candidate.
class JoinCostRevision {
 public:
  JoinCostRevision(const TrackStitchOptions& options, double sigma);
  double operator()(const TrackTable& tracks, std::size_t end, std::size_t start, double turn_weight,
                    float& turn_log_ratio) const;

 private:
  double quiet_was_, turn_was_;    // ln(1 − π), ln π of the first assignment
  double q_was_, q_now_, q_turn_;  // σ_a² of the first quiet model, the learnt one, the manoeuvring one
};

// The quiet model's σ_a learnt with the turn weight from a first assignment's joins (empirical
// Bayes, as the turn weight alone is, engine/pipeline/track_stitching.hpp): how sharply a target
// that did not manoeuvre continues across a gap is a property of the scene too (airliners on
// airways fly straight, the recorded family's targets drift between turns). For each σ_a of a
// geometric grid σ_k = manoeuvre_sigma · 2^{k/4}, k = 0 … 8 (manoeuvre_sigma to 4 manoeuvre_sigma,
// and no wider than turn_sigma), the weight π̂_σ(s) is span_mixture_weight's for the joins'
// d = ln N_turn − ln N_quiet(σ) and spans, and the σ_a is scored by
//     Σ_j ln[(1 − π̂_σ(s_j)) N(e_j; 0, S_quiet(σ)) + π̂_σ(s_j) N(e_j; 0, S_turn)] − (ln(σ / σ₀))² / (2 τ²),
// the joins' mixture likelihood at π̂_σ (the Beta prior of π̂ left out) plus a log-normal prior of
// median σ₀ = quiet_sigma_prior and log-sd τ = quiet_sigma_prior_sd (a normal in ln σ, the grid's
// own scale). The grid is climbed from its floor while the score rises, and the first maximum is
// kept (ties to the smaller σ_a): a file whose joins want the floor pays two fits, not nine. The
// prior weighs most in a file of few joins (the recorded family: 1-8 joins, σ_a 5.05-8.49 learnt),
// the joins in a large one. The floor is manoeuvre_sigma, the σ_a the first assignment used: the joins are
// those that assignment chose, and a σ_a below it is not learnt from them (widearea's likelihood rises to any
// floor offered, 3 → 1.5 → 0.5 m/s², while its fragment pairs fall 90.91 → 90.43 → 90.20 %;
// docs/design.md §4.10). `joins[j]` = (G₁'s last row, G₂'s start representative), `spans[j]` its
// span. O(J D³ + k (J D³ + span_mixture_weight)) for the k ≤ 9 σ_a climbed, the joins in parallel
// (the answer the same for any number of threads).
struct JoinRows {
  std::size_t end = 0, start = 0;
};
struct QuietModelFit {
  double sigma = 0.0;        // σ_a [m/s²]
  SpanMixtureWeight weight;  // π̂(s) at that σ_a
};
QuietModelFit learn_quiet_sigma(const TrackTable& tracks, std::span<const JoinRows> joins,
                                std::span<const float> spans, const TrackStitchOptions& options);

// ln det of row r's covariance predicted by dt (either sign) with q = σ_a²: how well a report,
// predicted to a common time, knows the state (the start's representative, track_stitching.hpp).
double predicted_log_det(const TrackTable& tracks, std::size_t r, double dt, double q);

// ln(e^a + e^b) without overflow (−inf when both are −inf).
double log_sum_exp(double a, double b);

}  // namespace trackassoc
