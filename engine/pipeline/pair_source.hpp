// The pair source stage (docs/design.md §1 and §4.3): which pairs of local tracks of two sensors get
// the sequential statistic λ (seed 000 Eq. 1–2) after the front end (engine/pipeline/front_end.hpp).
//
//   * all pairs (the dense paths, pipeline.hpp and pipeline_sd.hpp): λ for every n_a × n_b pair,
//     independent_sequential_statistic; O(n_a·n_b·K·D³).
//   * the per-scan candidate index (the sparse paths, sparse_pipeline.hpp and
//     sparse_sd_pipeline.hpp): candidate_pairs_for_gate (kernels/statistics/gate_candidates.hpp; a
//     lossless bound for the gate of `statistic`), pruned by the position-block bound
//     (prune_by_position_bound, also lossless), then λ on the candidates left and only the gated-in
//     pairs kept; O(K·n log n + hits + kept·K·D³). Both sparse paths call it with the same options,
//     so they see the same gated pairs (tests/engine/pipeline/test_pair_source.cpp).
//
// The partition that follows (engine/pipeline/partition.hpp) takes the gated pairs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/pipeline/front_end.hpp"
#include "kernels/core/allocation_gauge.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// All pairs of sensor positions a and b of `sensors`.
PairStatistic all_pairs_statistic(const AlignedSensors& sensors, int32_t a, int32_t b,
                                  const StatisticOptions& statistic);

// The candidate index of every pair a < b of the sensors, in one pass over the common times
// (kernels/statistics/gate_candidates.hpp): slot a·S + b holds the number of pairs of sensors a and b
// `found` within their bound at some scan, and `pairs`, those the index's count filter and then the
// position bound keep (sorted by (a, b); both filters lossless).
struct IndexedCandidates {
  CandidatePairs pairs;
  std::size_t found = 0;
};
// `gauge` (optional; kernels/core/allocation_gauge.hpp) is told every large buffer of the search
// and the prune before it is allocated (it throws to refuse); on return it holds the kept pairs'
// bytes (8 a pair).
std::vector<IndexedCandidates> indexed_candidates(const AlignedSensors& sensors,
                                                  const StatisticOptions& statistic, double radius_scale,
                                                  AllocationGauge* gauge = nullptr);

// λ on the candidates of sensors a and b, the gated-in pairs kept (sorted by (a, b)); the
// candidates' memory is released.
SparsePairStatistic gated_candidate_statistic(const AlignedSensors& sensors, int32_t a, int32_t b,
                                              CandidatePairs& candidates, const StatisticOptions& statistic);

}  // namespace trackassoc
