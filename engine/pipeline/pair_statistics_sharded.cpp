// The gated statistics over MPI ranks; see engine/pipeline/pair_statistics_sharded.hpp.
#include "engine/pipeline/pair_statistics_sharded.hpp"

#include <algorithm>
#include <string>

#include "kernels/statistics/gate_candidates.hpp"

namespace trackassoc {
namespace {

// The distinct tracks of `side` in increasing order.
std::vector<int32_t> rows_of(const std::vector<int32_t>& side) {
  std::vector<int32_t> rows(side);
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

// Each track of `side` as its position in `rows` (monotone: the pairs' order is kept).
std::vector<int32_t> renumbered(const std::vector<int32_t>& side, const std::vector<int32_t>& rows) {
  std::vector<int32_t> out(side.size());
  for (std::size_t q = 0; q < side.size(); ++q)
    out[q] = static_cast<int32_t>(std::lower_bound(rows.begin(), rows.end(), side[q]) - rows.begin());
  return out;
}

}  // namespace

PairStatisticsResult solve_pair_statistics(const StatisticOptions& statistic,
                                           const PairStatisticsItem& item) {
  const CandidatePairs kept = prune_by_position_bound(item.a, item.b, item.pairs, statistic);
  PairStatisticsResult r;
  r.kept = kept.size();
  r.gated = keep_in_gate(sparse_sequential_statistic(item.a, item.b, kept, statistic));
  return r;
}

std::vector<PairStatisticsResult> gated_statistics_sharded(distributed::Communicator& comm,
                                                           const AlignedSensors& sensors,
                                                           std::vector<CandidatePairs>& found,
                                                           const StatisticOptions& statistic) {
  const auto S = static_cast<std::size_t>(sensors.S());
  std::vector<PairStatisticsResult> out(S * S);
  std::vector<std::size_t> slot;  // the items: slots with candidates, in slot order
  std::vector<int64_t> id;
  std::vector<double> cost;  // the candidate count, the estimate of the pair's work
  for (std::size_t a = 0; a < S; ++a)
    for (std::size_t b = a + 1; b < S; ++b) {
      const std::size_t s = a * S + b;
      out[s].gated.n_a = sensors.aligned[a].n_tracks();
      out[s].gated.n_b = sensors.aligned[b].n_tracks();
      if (found[s].size() == 0) continue;
      slot.push_back(s);
      id.push_back(static_cast<int64_t>(s));
      cost.push_back(static_cast<double>(found[s].size()));
    }
  std::vector<std::vector<int32_t>> rows_a(slot.size()), rows_b(slot.size());
  auto solved = distributed::shard_items(comm, kPairStatisticsJob, "gated statistics of the sensor pairs",
                                         statistic, id, cost, [&](std::size_t k) {
                                           const std::size_t s = slot[k], a = s / S, b = s % S;
                                           const CandidatePairs& c = found[s];
                                           rows_a[k] = rows_of(c.a);
                                           rows_b[k] = rows_of(c.b);
                                           PairStatisticsItem item;
                                           copy_rows(sensors.aligned[a], rows_a[k], item.a);
                                           copy_rows(sensors.aligned[b], rows_b[k], item.b);
                                           item.pairs.n_a = static_cast<int32_t>(rows_a[k].size());
                                           item.pairs.n_b = static_cast<int32_t>(rows_b[k].size());
                                           item.pairs.a = renumbered(c.a, rows_a[k]);
                                           item.pairs.b = renumbered(c.b, rows_b[k]);
                                           return item;
                                         });
  for (std::size_t k = 0; k < slot.size(); ++k) {
    const std::size_t s = slot[k];
    PairStatisticsResult& r = out[s];
    r.kept = solved[k].kept;
    const int32_t n_a = r.gated.n_a, n_b = r.gated.n_b;
    r.gated = std::move(solved[k].gated);
    r.gated.n_a = n_a;
    r.gated.n_b = n_b;
    for (auto& i : r.gated.a) i = rows_a[k][i];
    for (auto& j : r.gated.b) j = rows_b[k][j];
    found[s] = CandidatePairs();
  }
  return out;
}

}  // namespace trackassoc
