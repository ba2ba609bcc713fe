// The cost of joining two fragments in fragment stitching (engine/pipeline/track_stitching.hpp has
// the rule, its references and its measurements): the gap statistic of one motion model (G₁'s end
// predicted forward and G₂'s start backward to the gap's midpoint, by constant velocity with the
// continuous white-noise acceleration Q of Bar-Shalom, Li, Kirubarajan 2001 §6.2.2), its diagonal
// pre-gate, and the two-model mixture's −ln p(e | same target). O(D³) per pair, no heap allocation
// (fixed-capacity Eigen matrices, D ≤ 6).
#pragma once

#include <cstddef>

#include "engine/pipeline/track_stitching.hpp"
#include "io/track_file.hpp"

namespace trackassoc {

// The gap statistic of engine/pipeline/track_stitching.hpp's rule for one model: G₁'s end (row `end`)
// predicted forward and G₂'s start (row `start`) backward to their midpoint with q = σ_a², m² and ln det(2π
// S).
struct GapStatistic {
  double m2 = 0.0, log_det = 0.0;
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

// ln det of row r's covariance predicted by dt (either sign) with q = σ_a²: how well a report,
// predicted to a common time, knows the state (the start's representative, track_stitching.hpp).
double predicted_log_det(const TrackTable& tracks, std::size_t r, double dt, double q);

// ln(e^a + e^b) without overflow (−inf when both are −inf).
double log_sum_exp(double a, double b);

}  // namespace trackassoc
