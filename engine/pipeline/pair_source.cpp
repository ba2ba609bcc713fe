// The pair source stage; see engine/pipeline/pair_source.hpp.
#include "engine/pipeline/pair_source.hpp"

#include "kernels/statistics/scan_candidates.hpp"

namespace trackassoc {

PairStatistic all_pairs_statistic(const AlignedSensors& sensors, int32_t a, int32_t b,
                                  const StatisticOptions& statistic) {
  return independent_sequential_statistic(sensors.aligned[a], sensors.aligned[b], statistic);
}

IndexedCandidates indexed_candidates(const AlignedSensors& sensors, int32_t a, int32_t b,
                                     const StatisticOptions& statistic, double radius_scale) {
  const AlignedTracks& ta = sensors.aligned[a];
  const AlignedTracks& tb = sensors.aligned[b];
  IndexedCandidates c;
  const CandidatePairs found = candidate_pairs_for_gate(ta, tb, statistic, radius_scale);
  c.found = found.size();
  c.pairs = prune_by_position_bound(ta, tb, found, statistic);
  return c;
}

SparsePairStatistic gated_candidate_statistic(const AlignedSensors& sensors, int32_t a, int32_t b,
                                              CandidatePairs& candidates, const StatisticOptions& statistic) {
  SparsePairStatistic s = keep_in_gate(
      sparse_sequential_statistic(sensors.aligned[a], sensors.aligned[b], candidates, statistic));
  CandidatePairs().a.swap(candidates.a);
  CandidatePairs().b.swap(candidates.b);
  return s;
}

}  // namespace trackassoc
