// The rows of each local track (see local_track_rows.hpp).
#include "kernels/core/local_track_rows.hpp"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace trackassoc {

std::size_t LocalTrackRows::find(Key k) const {
  const auto it = std::lower_bound(key.begin(), key.end(), k);
  return it != key.end() && *it == k ? static_cast<std::size_t>(it - key.begin()) : key.size();
}

LocalTrackRows local_track_rows(const TrackTable& t) {
  const std::size_t n = t.size();
  LocalTrackRows out;
  // Each row's track, numbered in order of first appearance.
  std::unordered_map<uint64_t, uint32_t> track_of;
  std::vector<uint32_t> track(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto [it, fresh] = track_of.try_emplace(packed_local_track(t.sensor[r], t.track[r]),
                                                  static_cast<uint32_t>(out.key.size()));
    if (fresh) out.key.emplace_back(t.sensor[r], t.track[r]);
    track[r] = it->second;
  }
  track_of = {};
  // The tracks in key order: rank[g] is the position of first-appearance track g.
  const std::size_t K = out.key.size();
  std::vector<uint32_t> order(K);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return out.key[a] < out.key[b]; });
  std::vector<uint32_t> rank(K);
  for (std::size_t k = 0; k < K; ++k) rank[order[k]] = static_cast<uint32_t>(k);
  std::vector<LocalTrackRows::Key> sorted_keys(K);
  for (std::size_t k = 0; k < K; ++k) sorted_keys[k] = out.key[order[k]];
  out.key = std::move(sorted_keys);
  // Counting sort of the rows by rank (stable: row order within a track).
  out.start.assign(K + 1, 0);
  for (std::size_t r = 0; r < n; ++r) ++out.start[rank[track[r]] + 1];
  for (std::size_t k = 0; k < K; ++k) out.start[k + 1] += out.start[k];
  out.row.resize(n);
  {
    std::vector<std::size_t> next(out.start.begin(), out.start.end() - 1);
    for (std::size_t r = 0; r < n; ++r) out.row[next[rank[track[r]]]++] = r;
  }
  // Time order within each track, ties in row order.
  auto by_time = [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; };
  for (std::size_t k = 0; k < K; ++k) {
    const auto first = out.row.begin() + static_cast<std::ptrdiff_t>(out.start[k]);
    const auto last = out.row.begin() + static_cast<std::ptrdiff_t>(out.start[k + 1]);
    if (!std::is_sorted(first, last, by_time)) std::stable_sort(first, last, by_time);
  }
  return out;
}

double bytes_of_local_track_rows(std::size_t rows, std::size_t tracks) {
  // Per row: its index (8) and its track (4); per track: key (8), offset (8), order and rank (8),
  // the next-free offsets (8) and a hash node with its bucket (~48).
  return static_cast<double>(rows) * 12.0 + static_cast<double>(tracks) * 80.0;
}

}  // namespace trackassoc
