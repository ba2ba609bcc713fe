// Association metrics (docs/design.md §3 /metrics, seed 000 §4 "correct association rate").
//
// Evaluated per target by per-row truth, over the sensors an association covers. A local track is
// a (sensor, track) key of the /tracks given, so a recycled number `associate` split into new
// tracks (engine/pipeline/track_hygiene.hpp) is scored as its pieces; its target is the majority
// of its rows' truth (local_track_truth: the most frequent id ≥ 0, ties to the lowest; −1, a false
// track, when no row has one). A target "needs association" when at least two covered sensors
// hold a local track of it. An output group is the tuples sharing a target number
// (/associations/NAME/target), or each tuple alone when the record has none. For each such target T:
//   correct  — one output group holds exactly T's local tracks (all of them, nothing else);
//   false    — some track of T shares a group with a track of another target (or a false track);
//   missed   — otherwise: T's tracks are split over several groups but never mixed with others.
// The three rates are fractions of the targets that need association, so they sum to 1.
// A target seen by 3 of 4 sensors is correct when its 3 tracks are grouped (dummy for the 4th).
// Local tracks whose truth is unknown (-1) make a target-less tuple count as false when grouped
// with anything; a file without truth gives has_truth = false. False tuples are counted apart: a
// tuple of ≥ 2 members is false when it joins tracks of different targets, or a false track with
// anything.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

enum class TargetOutcome { kCorrect, kFalse, kMissed };

struct AssociationMetrics {
  bool has_truth = false;
  int32_t targets = 0;  // targets that need association
  int32_t correct = 0, false_associations = 0, missed = 0;
  // Output tuples with ≥ 2 members, and those among them that join tracks of different targets or
  // a false track (truth −1) with anything.
  int32_t linked_tuples = 0, false_tuples = 0;
  double correct_rate = 0.0, false_rate = 0.0, missed_rate = 0.0;
};

// What the counts are made of (the map of engine/report/association_map.hpp draws them): the
// outcome of each target that needs association, and the rows of the false tuples.
struct AssociationDetail {
  std::map<int32_t, TargetOutcome> outcome;
  std::vector<std::size_t> false_tuple_rows;
};

// The target of each local track of the sensors `record` covers, keyed by (tuple column, track):
// the most frequent non-negative truth id of its rows, -1 when it has none (a false track).
std::map<std::pair<int32_t, int32_t>, int32_t> local_track_truth(const TrackTable& tracks,
                                                                 const std::vector<Sensor>& sensors,
                                                                 const AssociationRecord& record);

// `sensors` gives the column order of record.tuples (the /sensors order).
// `detail`, when given, receives what the counts are made of.
AssociationMetrics evaluate_association(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                        const AssociationRecord& record, AssociationDetail* detail = nullptr);

MetricsRecord to_metrics_record(const std::string& name, const AssociationMetrics& m);

}  // namespace trackassoc
