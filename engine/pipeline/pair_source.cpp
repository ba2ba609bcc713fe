// The pair source stage; see engine/pipeline/pair_source.hpp.
#include "engine/pipeline/pair_source.hpp"

#include "kernels/core/parallel.hpp"
#include "kernels/statistics/gate_candidates.hpp"

namespace trackassoc {

PairStatistic all_pairs_statistic(const AlignedSensors& sensors, int32_t a, int32_t b,
                                  const StatisticOptions& statistic) {
  return independent_sequential_statistic(sensors.aligned[a], sensors.aligned[b], statistic);
}

std::vector<IndexedCandidates> indexed_candidates(const AlignedSensors& sensors,
                                                  const StatisticOptions& statistic, double radius_scale,
                                                  AllocationGauge* gauge) {
  std::vector<const AlignedTracks*> x;
  for (const AlignedTracks& t : sensors.aligned) x.push_back(&t);
  std::vector<std::size_t> within;  // per slot, the pairs the index found before its count filter
  std::vector<CandidatePairs> found = candidate_pairs_for_gate(x, statistic, radius_scale, gauge, &within);
  const std::size_t S = x.size();
  std::vector<IndexedCandidates> out(found.size());
  std::vector<std::pair<std::size_t, std::size_t>> sensor_pairs;
  for (std::size_t a = 0; a < S; ++a)
    for (std::size_t b = a + 1; b < S; ++b) sensor_pairs.emplace_back(a, b);
  // The pairs of sensors in parallel (most are small; each prune is parallel inside too).
  parallel_for_range(sensor_pairs.size(), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const auto [a, b] = sensor_pairs[q];
      IndexedCandidates& c = out[a * S + b];
      c.found = within[a * S + b];
      c.pairs = prune_by_position_bound(*x[a], *x[b], found[a * S + b], statistic, gauge);
      const double freed =
          static_cast<double>(found[a * S + b].a.capacity() + found[a * S + b].b.capacity()) *
          sizeof(int32_t);
      found[a * S + b] = CandidatePairs();
      gauge_release(gauge, freed);
    }
  });
  return out;
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
