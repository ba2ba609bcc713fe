// The rows of each local track of a track table, once for every stage that walks a track's reports
// in time order (the reader's repeated-report check, track hygiene, the registration stage, fusion
// and its accuracy).
//
// A local track is a key (sensor id, track number). The result is a compressed layout: the keys in
// ascending (sensor, track) order, and for key k its rows rows(k), in ascending time, rows with the
// same time in row order (what std::stable_sort by time of the rows in row order gives).
// Algorithm: a hash of each row's key to its track, a sort of the K distinct keys, a counting sort
// of the rows by track (stable: row order within a track), then each track's rows sorted by time
// only where they are not already in time order (a recording usually lists a track's reports in
// time order). O(n + K log K + Σ_k n_k log n_k over the unsorted tracks) time, O(n + K) memory:
// n row indices, K keys and offsets, and the hash (bytes_of_local_track_rows). Serial: it runs in
// the reader, which may be a forked child (io/isolated_run.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "kernels/core/types.hpp"

namespace trackassoc {

struct LocalTrackRows {
  using Key = std::pair<int32_t, int32_t>;  // (sensor id, track number)
  std::vector<Key> key;                     // ascending
  std::vector<std::size_t> start;           // key.size() + 1 offsets into row
  std::vector<std::size_t> row;             // every row of the table, grouped by key

  std::size_t size() const { return key.size(); }
  std::span<const std::size_t> rows(std::size_t k) const {
    return {row.data() + start[k], start[k + 1] - start[k]};
  }
  // The position of `k` in key, or size() when the table has no such local track (binary search).
  std::size_t find(Key k) const;
};

LocalTrackRows local_track_rows(const TrackTable& t);

// A local track's key as one 64-bit number (sensor id in the high half), for hashing.
inline uint64_t packed_local_track(int32_t sensor, int32_t track) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(sensor)) << 32) | static_cast<uint32_t>(track);
}

// An upper bound on the bytes local_track_rows holds while it builds its result, for a table of
// `rows` reports and at most `tracks` local tracks (for --memory-budget checks).
double bytes_of_local_track_rows(std::size_t rows, std::size_t tracks);

}  // namespace trackassoc
