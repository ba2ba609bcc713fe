// The gated statistics of the default path shared over MPI ranks (docs/design.md §8, docs/mpi.md;
// issue 31 item 5). After rank 0's candidate index (kernels/statistics/scan_candidates.hpp), each
// pair of sensors (a, b) with candidates is an item of engine/distributed/shard_items.hpp: the
// aligned tracks of a and of b that its candidates name (copy_rows, each over its span), and the
// candidates renumbered to them. Where it lands, the item is pruned by the position bound
// (prune_by_position_bound) and λ is computed on what is left, the gated-in pairs kept
// (sparse_sequential_statistic, keep_in_gate): the two steps one process runs in its candidate and
// statistic stages (engine/pipeline/pair_source.hpp). Rank 0 renumbers the gated pairs back.
//
// Why the result is that of one process, bit for bit: both steps are per pair of tracks (a serial
// loop over the pair's common times on its own two tracks' cells), and the only sensor-wide input
// is the gate's table size (min of the longest spans), which caches thresholds without changing
// them (SequentialGate::threshold is a function of the scan count alone); renumbering is monotone,
// so the pairs stay sorted by (a, b) and keep their order.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "engine/distributed/codec.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/distributed/shard_items.hpp"
#include "engine/pipeline/front_end.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// One pair of sensors: its candidates' tracks and the candidates, renumbered to them.
struct PairStatisticsItem {
  AlignedTracks a, b;
  CandidatePairs pairs;
};
// The candidates the position bound kept, and the gated-in pairs (in the item's numbering).
struct PairStatisticsResult {
  uint64_t kept = 0;
  SparsePairStatistic gated;
};

PairStatisticsResult solve_pair_statistics(const StatisticOptions& statistic, const PairStatisticsItem& item);

constexpr auto wire_codec(std::type_identity<AlignedTracks>) {
  return distributed::codec<AlignedTracks>(
      "aligned tracks", &AlignedTracks::sensor, &AlignedTracks::dim, &AlignedTracks::n_times,
      &AlignedTracks::times, &AlignedTracks::track, &AlignedTracks::truth, &AlignedTracks::span_begin,
      &AlignedTracks::span_offset, &AlignedTracks::state, &AlignedTracks::cov, &AlignedTracks::valid);
}
constexpr auto wire_codec(std::type_identity<CandidatePairs>) {
  return distributed::codec<CandidatePairs>("candidate pairs", &CandidatePairs::n_a, &CandidatePairs::n_b,
                                            &CandidatePairs::a, &CandidatePairs::b);
}
constexpr auto wire_codec(std::type_identity<SparsePairStatistic>) {
  return distributed::codec<SparsePairStatistic>("gated pair statistic", &SparsePairStatistic::n_a,
                                                 &SparsePairStatistic::n_b, &SparsePairStatistic::a,
                                                 &SparsePairStatistic::b, &SparsePairStatistic::lambda,
                                                 &SparsePairStatistic::dof, &SparsePairStatistic::in_gate);
}
constexpr auto wire_codec(std::type_identity<PairStatisticsItem>) {
  return distributed::codec<PairStatisticsItem>("sensor pair's candidates", &PairStatisticsItem::a,
                                                &PairStatisticsItem::b, &PairStatisticsItem::pairs);
}
constexpr auto wire_codec(std::type_identity<PairStatisticsResult>) {
  return distributed::codec<PairStatisticsResult>("sensor pair's gated statistic",
                                                  &PairStatisticsResult::kept, &PairStatisticsResult::gated);
}

// The job (kind 1; the components' job is kind 0): the header is the statistic's options (a plain
// struct, its bytes).
inline constexpr distributed::ItemJob<StatisticOptions, PairStatisticsItem, PairStatisticsResult>
    kPairStatisticsJob{"sensor pair", "candidate pairs",
                       [](const PairStatisticsItem& x) { return x.pairs.size(); }, &solve_pair_statistics, 1};

// Rank 0 (the other ranks serve kPairStatisticsJob, serve_sd_components): the candidates of every
// slot a·S + b (a < b) of `sensors`, as the index found them, pruned and gated over the ranks; the
// candidates are released. Slot s of the result is what one process's prune_by_position_bound and
// gated_candidate_statistic give for it: `kept` the pruned count, `gated` in the sensors' numbering.
std::vector<PairStatisticsResult> gated_statistics_sharded(distributed::Communicator& comm,
                                                           const AlignedSensors& sensors,
                                                           std::vector<CandidatePairs>& found,
                                                           const StatisticOptions& statistic);

}  // namespace trackassoc
