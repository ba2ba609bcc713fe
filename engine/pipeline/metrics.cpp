#include "engine/pipeline/metrics.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace trackassoc {

std::map<std::pair<int32_t, int32_t>, int32_t> local_track_truth(const TrackTable& tracks,
                                                                 const std::vector<Sensor>& sensors,
                                                                 const AssociationRecord& record) {
  const int32_t S = record.num_sensors;
  const std::size_t K = record.num_tuples();
  // Which sensors does the association cover? Those with any track in a tuple.
  std::vector<char> covered(S, 0);
  for (std::size_t q = 0; q < K; ++q)
    for (int32_t s = 0; s < S; ++s)
      if (record.tuples[q * S + s] >= 0) covered[s] = 1;

  // Truth id of each (sensor column, local track): the most frequent non-negative id of its rows.
  std::map<std::pair<int32_t, int32_t>, std::map<int32_t, int32_t>> votes;
  std::map<int32_t, int32_t> column_of_sensor;
  for (int32_t s = 0; s < static_cast<int32_t>(sensors.size()); ++s) column_of_sensor[sensors[s].id] = s;
  for (std::size_t r = 0; r < tracks.size(); ++r) {
    auto it = column_of_sensor.find(tracks.sensor[r]);
    if (it == column_of_sensor.end() || it->second >= S || !covered[it->second]) continue;
    ++votes[{it->second, tracks.track[r]}][tracks.truth[r]];
  }
  std::map<std::pair<int32_t, int32_t>, int32_t> truth_of;
  for (const auto& [key, counts] : votes) {
    int32_t best = -1, best_count = 0;
    for (const auto& [id, c] : counts)
      if (id >= 0 && c > best_count) best = id, best_count = c;
    truth_of[key] = best;
  }
  return truth_of;
}

AssociationMetrics evaluate_association(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                        const AssociationRecord& record, AssociationDetail* detail) {
  AssociationMetrics m;
  const int32_t S = record.num_sensors;
  const std::size_t K = record.num_tuples();
  const std::map<std::pair<int32_t, int32_t>, int32_t> truth_of = local_track_truth(tracks, sensors, record);
  for (const auto& entry : truth_of) m.has_truth |= entry.second >= 0;
  if (!m.has_truth) return m;

  // Tracks of each target, per covered sensor.
  std::map<int32_t, std::set<std::pair<int32_t, int32_t>>> tracks_of_target;
  for (const auto& [key, id] : truth_of)
    if (id >= 0) tracks_of_target[id].insert(key);

  // Group of each track: its tuple, or its target when the record has target numbers (segments
  // of one target over time, engine/pipeline/track_segments.hpp); the tracks of each group.
  const bool targets = record.target.size() == K;
  std::map<std::pair<int32_t, int32_t>, std::size_t> group_of;
  std::map<std::size_t, std::set<std::pair<int32_t, int32_t>>> group_tracks;
  for (std::size_t q = 0; q < K; ++q)
    for (int32_t s = 0; s < S; ++s)
      if (record.tuples[q * S + s] >= 0) {
        const std::pair<int32_t, int32_t> key{s, record.tuples[q * S + s]};
        const std::size_t g = targets ? static_cast<std::size_t>(record.target[q]) : q;
        group_of[key] = g;
        group_tracks[g].insert(key);
      }

  for (const auto& [target, members] : tracks_of_target) {
    std::set<int32_t> member_sensors;
    for (const auto& key : members) member_sensors.insert(key.first);
    if (member_sensors.size() < 2) continue;  // seen by one sensor only: nothing to associate
    ++m.targets;
    bool mixed = false;
    std::set<std::size_t> groups;
    for (const auto& key : members) {
      auto it = group_of.find(key);
      if (it == group_of.end()) continue;  // track absent from the association: counts as split
      groups.insert(it->second);
      for (const auto& other_key : group_tracks[it->second]) {
        auto t = truth_of.find(other_key);
        const int32_t other = t == truth_of.end() ? -1 : t->second;
        if (other != target) mixed = true;
      }
    }
    const bool complete = !mixed && groups.size() == 1 && group_tracks[*groups.begin()] == members;
    const TargetOutcome outcome = mixed      ? TargetOutcome::kFalse
                                  : complete ? TargetOutcome::kCorrect
                                             : TargetOutcome::kMissed;
    if (detail) detail->outcome[target] = outcome;
    ++(outcome == TargetOutcome::kFalse     ? m.false_associations
       : outcome == TargetOutcome::kCorrect ? m.correct
                                            : m.missed);
  }
  // False tuples: ≥ 2 members that are not all tracks of one target (a false track, truth −1, with
  // anything is false).
  for (std::size_t q = 0; q < K; ++q) {
    int32_t members = 0, first = -2;
    bool mixed = false;
    for (int32_t s = 0; s < S; ++s) {
      const int32_t trk = record.tuples[q * S + s];
      if (trk < 0) continue;
      ++members;
      auto t = truth_of.find({s, trk});
      const int32_t id = t == truth_of.end() ? -1 : t->second;
      if (id < 0 || (first != -2 && id != first)) mixed = true;
      first = id;
    }
    if (members >= 2) {
      ++m.linked_tuples;
      m.false_tuples += mixed;
      if (mixed && detail) detail->false_tuple_rows.push_back(q);
    }
  }
  if (m.targets > 0) {
    m.correct_rate = static_cast<double>(m.correct) / m.targets;
    m.false_rate = static_cast<double>(m.false_associations) / m.targets;
    m.missed_rate = static_cast<double>(m.missed) / m.targets;
  }
  return m;
}

MetricsRecord to_metrics_record(const std::string& name, const AssociationMetrics& m) {
  MetricsRecord r;
  r.name = name;
  r.correct_rate = m.correct_rate;
  r.false_rate = m.false_rate;
  r.missed_rate = m.missed_rate;
  r.tables["n_targets"] = {static_cast<double>(m.targets)};
  r.tables["n_correct"] = {static_cast<double>(m.correct)};
  r.tables["n_false"] = {static_cast<double>(m.false_associations)};
  r.tables["n_missed"] = {static_cast<double>(m.missed)};
  r.tables["n_linked_tuples"] = {static_cast<double>(m.linked_tuples)};
  r.tables["n_false_tuples"] = {static_cast<double>(m.false_tuples)};
  return r;
}

}  // namespace trackassoc
