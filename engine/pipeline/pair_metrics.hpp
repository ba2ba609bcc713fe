// Pair-level association metrics (issue 31 "Done when"): what fraction of the pairs of local
// tracks that should be linked are, and what fraction of the linked pairs are right. Beside the
// per-target correct rate of engine/pipeline/metrics.hpp, and on the same keys: a local track is a
// (sensor, track) key of /tracks on a sensor the association covers, its truth the majority of its
// rows' truth (local_track_truth; −1, a false track, when none).
//
// "One target in the output": tracks in one tuple are one target, and so are the tuples sharing a
// /associations/NAME/target number (when the record has them); the relation is closed
// transitively (union-find), so a track in two tuples joins them. A track in no tuple is alone.
//   coexisting cross-sensor pair — two keys on different sensors with the same truth (≥ 0) whose
//     report intervals [first t, last t] overlap; recall = the fraction in one output target;
//   same-sensor fragment pair — two keys of one sensor with the same truth that follow each other:
//     sorted by first report time, key j is the next one after key i and starts after i's last
//     report; recall likewise;
//   pair precision — of all pairs of keys the output puts in one target (m·(m−1)/2 per target of
//     m keys, across and within sensors), the fraction with the same truth ≥ 0 (a false track,
//     truth −1, linked with anything is wrong).
// A rate with nothing to count is NaN.
#pragma once

#include <cstdint>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

struct PairMetrics {
  int64_t coexisting = 0, coexisting_linked = 0;
  int64_t fragments = 0, fragments_linked = 0;
  int64_t linked_pairs = 0, linked_pairs_same_truth = 0;
  double coexisting_recall = 0.0, fragment_recall = 0.0, precision = 0.0;
};

// `sensors` gives the column order of record.tuples (the /sensors order).
PairMetrics evaluate_pairs(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                           const AssociationRecord& record);

// Adds the counts and rates to a /metrics record (tables n_coexisting_pairs, n_coexisting_linked,
// coexisting_recall, n_fragment_pairs, n_fragment_linked, fragment_recall, n_linked_pairs,
// n_linked_pairs_same_truth, pair_precision).
void add_pair_metrics(MetricsRecord& record, const PairMetrics& m);

}  // namespace trackassoc
