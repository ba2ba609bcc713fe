// Pair-level association metrics; see engine/pipeline/pair_metrics.hpp.
#include "engine/pipeline/pair_metrics.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include "engine/pipeline/metrics.hpp"
#include "kernels/assignment/clusters.hpp"

namespace trackassoc {

namespace {

uint64_t code(int32_t column, int32_t track) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(column)) << 32) | static_cast<uint32_t>(track);
}

double rate(int64_t part, int64_t whole) {
  return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole)
                   : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

PairMetrics evaluate_pairs(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                           const AssociationRecord& record) {
  PairMetrics m;
  const int32_t S = record.num_sensors;
  const std::size_t K = record.num_tuples();
  // Keys: those with rows on the covered sensors, then any key of a tuple without rows (truth −1).
  struct Key {
    int32_t column = 0, truth = -1;
    double first = std::numeric_limits<double>::infinity(), last = -std::numeric_limits<double>::infinity();
  };
  std::vector<Key> keys;
  std::unordered_map<uint64_t, std::size_t> index;
  for (const auto& [key, truth] : local_track_truth(tracks, sensors, record)) {
    index.emplace(code(key.first, key.second), keys.size());
    keys.push_back({key.first, truth});
  }
  std::unordered_map<int32_t, int32_t> column_of_sensor;
  for (int32_t s = 0; s < static_cast<int32_t>(sensors.size()); ++s) column_of_sensor[sensors[s].id] = s;
  for (std::size_t r = 0; r < tracks.size(); ++r) {
    auto c = column_of_sensor.find(tracks.sensor[r]);
    if (c == column_of_sensor.end()) continue;
    auto it = index.find(code(c->second, tracks.track[r]));
    if (it == index.end()) continue;  // a sensor the association does not cover
    Key& k = keys[it->second];
    k.first = std::min(k.first, tracks.t[r]);
    k.last = std::max(k.last, tracks.t[r]);
  }
  auto key_of = [&](int32_t column, int32_t track) {
    auto [it, added] = index.emplace(code(column, track), keys.size());
    if (added) keys.push_back({column, -1});
    return it->second;
  };
  // Output targets: tuples, joined by their target numbers.
  std::vector<std::size_t> tuple_keys;
  std::vector<std::pair<std::size_t, std::size_t>> joins;
  std::unordered_map<int32_t, std::size_t> first_key_of_target;
  for (std::size_t q = 0; q < K; ++q) {
    tuple_keys.clear();
    for (int32_t s = 0; s < S; ++s)
      if (record.tuples[q * S + s] >= 0) tuple_keys.push_back(key_of(s, record.tuples[q * S + s]));
    if (tuple_keys.empty()) continue;
    for (std::size_t i = 1; i < tuple_keys.size(); ++i) joins.push_back({tuple_keys[0], tuple_keys[i]});
    if (record.target.size() == K) {
      auto [it, added] = first_key_of_target.emplace(record.target[q], tuple_keys[0]);
      if (!added) joins.push_back({it->second, tuple_keys[0]});
    }
  }
  UnionFind uf(static_cast<int32_t>(keys.size()));
  for (const auto& [a, b] : joins) uf.unite(static_cast<int32_t>(a), static_cast<int32_t>(b));

  // Keys of each truth, by first report.
  std::map<int32_t, std::vector<std::size_t>> of_truth;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (keys[i].truth >= 0 && keys[i].first <= keys[i].last) of_truth[keys[i].truth].push_back(i);
  for (auto& [truth, list] : of_truth) {
    std::sort(list.begin(), list.end(), [&](std::size_t a, std::size_t b) {
      return keys[a].first != keys[b].first ? keys[a].first < keys[b].first : a < b;
    });
    std::map<int32_t, std::size_t> previous_on_column;  // the latest-starting key so far per sensor
    for (std::size_t x = 0; x < list.size(); ++x) {
      const Key& a = keys[list[x]];
      for (std::size_t y = x + 1; y < list.size() && keys[list[y]].first <= a.last; ++y)
        if (keys[list[y]].column != a.column) {
          ++m.coexisting;
          m.coexisting_linked +=
              uf.find(static_cast<int32_t>(list[x])) == uf.find(static_cast<int32_t>(list[y]));
        }
      auto prev = previous_on_column.find(a.column);
      if (prev != previous_on_column.end() && a.first > keys[prev->second].last) {
        ++m.fragments;
        m.fragments_linked +=
            uf.find(static_cast<int32_t>(prev->second)) == uf.find(static_cast<int32_t>(list[x]));
      }
      previous_on_column[a.column] = list[x];
    }
  }
  // Linked pairs per output target: all pairs, and those of one truth ≥ 0.
  std::unordered_map<std::size_t, std::map<int32_t, int64_t>> truths_of_root;
  for (std::size_t i = 0; i < keys.size(); ++i)
    ++truths_of_root[uf.find(static_cast<int32_t>(i))][keys[i].truth];
  for (const auto& [root, counts] : truths_of_root) {
    int64_t members = 0;
    for (const auto& [truth, c] : counts) {
      members += c;
      if (truth >= 0) m.linked_pairs_same_truth += c * (c - 1) / 2;
    }
    m.linked_pairs += members * (members - 1) / 2;
  }
  m.coexisting_recall = rate(m.coexisting_linked, m.coexisting);
  m.fragment_recall = rate(m.fragments_linked, m.fragments);
  m.precision = rate(m.linked_pairs_same_truth, m.linked_pairs);
  return m;
}

void add_pair_metrics(MetricsRecord& r, const PairMetrics& m) {
  auto put = [&](const char* name, double v) { r.tables[name] = {v}; };
  put("n_coexisting_pairs", static_cast<double>(m.coexisting));
  put("n_coexisting_linked", static_cast<double>(m.coexisting_linked));
  put("coexisting_recall", m.coexisting_recall);
  put("n_fragment_pairs", static_cast<double>(m.fragments));
  put("n_fragment_linked", static_cast<double>(m.fragments_linked));
  put("fragment_recall", m.fragment_recall);
  put("n_linked_pairs", static_cast<double>(m.linked_pairs));
  put("n_linked_pairs_same_truth", static_cast<double>(m.linked_pairs_same_truth));
  put("pair_precision", m.precision);
}

}  // namespace trackassoc
